// The assessment colours of a region of the loop arrangement (paper §4.2).
//
// assess_region(disc, singularities, valence, total_curvature) -> RegionColour
//   red     the region is not a disc: the loops imply no valid layout, more
//           strips are needed to split it
//   orange  it holds more than one cross-field singularity (§6.1): several
//           pronounced curvature extrema that would be better separate
//           irregular vertices (separate regions)
//   yellow  its valence v and total Gaussian curvature K disagree: ideally
//           K = (4 - v) pi / 2, and |v - (4 - 2K/pi)| > 1 is flagged
//           (beyond rounding: exactly 1 is not)
//   none    otherwise
// The first that applies wins. A layout is valid iff no region is red.
#pragma once

#include <cstdint>

namespace stripweave {

enum class RegionColour : std::uint8_t { None = 0, Red = 1, Orange = 2, Yellow = 3 };

// The valence that suits a region's total curvature K: 4 - 2K/pi.
double ideal_valence(double total_curvature);

RegionColour assess_region(bool disc, int singularities, int valence, double total_curvature);

// "none", "red", "orange" or "yellow".
const char* colour_name(RegionColour colour);

}  // namespace stripweave
