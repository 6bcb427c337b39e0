// The rims of a part (closed creases that meet no other crease and no open
// boundary: around a bore, a boss, a shaft's end) and how often the loops of
// an arrangement cross each (issue 17).
//
// Why: a crease lies on primal edges only as a chain between primal
// vertices, and a rim has no junction of its own, so its primal vertices are
// where loops cross it: k crossings cut it into k pieces, each in its own
// region (whose one vertex goes on it), joined by k primal edges. With k = 0
// the rim lies inside one region, a cycle no vertex can carry; with k = 1 it
// would be one primal edge from a vertex to itself. So a rim lacks
// max(0, 2 - k) crossings. (Two crossings can do: the two loops through a
// bore each cross both its rims once, and each rim is two primal edges
// between two vertices, a patch on either side of each. Where one loop makes
// both, each half of the rim leaves its region twice across that loop's arc,
// which the regions' star test flags, crease_structure.h.)
//
// The lack is a property of the rim, not of a region, and the regions' star
// test does not see it: a loop across a rim cuts it into pieces, which each
// region's excess counts (pieces and exits beyond one) until further loops
// part them. So the excess rises on the way to a conforming layout, and a
// weave that lowers it one loop at a time may never cross a rim (a boss on a
// plate: excess 16 with no loop, 36 with the two loops across both rims that
// a conforming layout there has, 0 with six more). The weave counts the lack
// before the excess once its crease phase stalls (weave.py, rim_lack).
//
// crease_rims(arrangement, refined_crease, triangle_region) -> [CreaseRim]
//   Input : the arrangement (its refined mesh and loop edges), per refined
//           edge whether it is a crease (crease_structure.h), per refined
//           triangle its region.
//   Output: per rim (a component of the crease edges whose vertices all have
//           crease degree 2 and none lies on the open boundary): how often
//           loops cross it (a vertex on a loop where neither crease edge is
//           a loop edge: a loop along the rim crosses nothing, the star test
//           flags it), its lack, and where a loop would add crossings: the
//           vertex halfway (by length) along its longest stretch between
//           crossings (any vertex of an uncrossed rim: its first by index),
//           the direction across the rim there in its mean tangent plane
//           (§5.6: a loop crosses a crease orthogonally), and that vertex's
//           region.
//   Cost  : linear in the refined mesh.
#pragma once

#include "stripweave/layout/loop_arrangement.h"

#include <cstdint>

namespace stripweave {

// Crossings a rim needs to carry primal vertices and edges (above).
constexpr int kRimCrossings = 2;

struct CreaseRim {
  int crossings = 0;
  int lack = 0;                // max(0, kRimCrossings - crossings)
  Index seed = kInvalid;       // refined vertex where a loop would add crossings
  Vec3 across = Vec3::Zero();  // unit, normalized frame; the direction across the rim there
  Index region = kInvalid;     // the seed's region
};

std::vector<CreaseRim> crease_rims(const LoopArrangement& arrangement, const std::vector<std::uint8_t>& refined_crease,
                                   const std::vector<Index>& triangle_region);

}  // namespace stripweave
