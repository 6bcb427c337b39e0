// The assessment colours of a region of the loop arrangement (paper §4.2,
// and issue 17's crease colour).
//
// assess_region(disc, crease_problem, extrema, valence, total_curvature) -> RegionColour
//   red     the region is not a disc: the loops imply no valid layout, more
//           strips are needed to split it
//   crease  the region keeps the layout from being crease-conforming
//           (crease_structure.h: two crease junctions in it, crease pieces
//           that do not meet, a loop crossing on a crease, a loop along a
//           crease, ...): more strips are needed there, or other routes
//   orange  it holds more than one pronounced curvature extremum of one
//           kind: two or more cross-field singularities of the same sign
//           (§6.1). Such extrema are best separate irregular vertices. A
//           +1/4, -1/4 pair is no extremum (its curvature cancels: the
//           dipoles noise leaves on a scan), so it is not counted.
//   yellow  its valence v and total Gaussian curvature K disagree: ideally
//           K = (4 - v) pi / 2, and |v - (4 - 2K/pi)| > 1 is flagged
//           (beyond rounding: exactly 1 is not)
//   none    otherwise
// The first that applies wins. A layout is valid iff no region is red; it
// can be crease-conforming only if no region is crease.
#pragma once

#include <cstdint>
#include <vector>

namespace stripweave {

enum class RegionColour : std::uint8_t { None = 0, Red = 1, Orange = 2, Yellow = 3, Crease = 4 };

// The valence that suits a region's total curvature K: 4 - 2K/pi.
double ideal_valence(double total_curvature);

// Curvature extrema of one kind beyond the first that one vertex could take:
// max(0, positive - 1) + max(0, negative - 1) over the singularities'
// quarter indices (0 for a lone singularity or a +- pair).
int excess_extrema(const std::vector<int>& quarter_indices);

RegionColour assess_region(bool disc, bool crease_problem, int excess_extrema, int valence, double total_curvature);

// "none", "red", "orange", "yellow" or "crease".
const char* colour_name(RegionColour colour);

}  // namespace stripweave
