// One triangle of the surface cut by the loops' chords (a step of the loop
// arrangement, loop_arrangement.h).
//
// split_by_chords(input) -> ChordSplit
//   Input (2D, in the triangle's own plane):
//     corners        the triangle, counter-clockwise
//     boundary       the points on its boundary in counter-clockwise order:
//                    corner 0, the points inside side 0 (corner 0 -> 1),
//                    corner 1, the points inside side 1, corner 2, side 2;
//                    all distinct (the caller has snapped near-coincident
//                    points together)
//     corner_at[k]   the position of corner k in `boundary` (corner_at[0] = 0)
//     chords         straight chords, each joining two boundary positions
//                    that do not lie on one common side (a step of a loop
//                    running along a side is not a chord: it is the side)
//     tolerance      crossings closer than this along a chord are one point
//   Method: which chords cross is decided combinatorially and exactly: two
//           chords with distinct endpoints cross inside the triangle iff
//           their endpoints interleave on the boundary cycle, and chords
//           sharing an endpoint do not. Only where they cross is computed
//           (line intersection). Along each chord the crossings are sorted;
//           crossings nearer than the tolerance merge into one vertex
//           (several chords through one point), transitively and until no
//           chord visits a merged vertex twice. Chords with the same two
//           endpoints are one. Two chords meet at most once: vertices they
//           would share twice (only through merging) are one. The pieces
//           form a planar graph whose rotation system is combinatorial too:
//           seen from any vertex, the pieces leaving it are ordered like the
//           boundary points they head for (the triangle is convex), so no
//           rounded coordinate can flip a tiny piece; its faces are traced
//           and checked: V - E + F = 2 with the boundary cycle as the outer
//           face. Faces are convex (every chord spans the triangle); each
//           is fanned from the corner that gives the best smallest
//           triangle, or from a Steiner point at its centroid when every
//           corner fan would have a flat triangle (collinear points on the
//           sides next to every corner).
//           Fallback (never seen on real loops; it needs crossings closer
//           than the tolerance that the merging could not make consistent):
//           all chords pass through one interior point, a star. That keeps
//           the topology valid (a manifold disc) at the price of making the
//           chords meet there; `star` reports it.
//   Output:
//     points          new vertices: the crossings (the first `crossings`),
//                     then Steiner points; local id of points[i] is
//                     boundary.size() + i (local ids below that are
//                     boundary positions)
//     crossing_chords per crossing, the chords through it (input indices)
//     triangles       the pieces, counter-clockwise, in local ids
//     chord_vertices  per input chord, its local vertices from its first
//                     endpoint to its second (crossings in between)
//     star            the fallback was used
#pragma once

#include "stripweave/core/types.h"

namespace stripweave {

struct ChordSplitInput {
  std::array<Vec2, 3> corners;
  std::vector<Vec2> boundary;
  std::array<Index, 3> corner_at{0, 0, 0};
  std::vector<std::array<Index, 2>> chords;
  double tolerance = 0;
};

struct ChordSplit {
  std::vector<Vec2> points;
  Index crossings = 0;
  std::vector<std::vector<Index>> crossing_chords;
  std::vector<std::array<Index, 3>> triangles;
  std::vector<std::vector<Index>> chord_vertices;
  bool star = false;
};

ChordSplit split_by_chords(const ChordSplitInput& input);

// True if boundary positions i and j lie on one closed side of the triangle
// (both on side k or at its end corners).
bool on_common_side(const std::array<Index, 3>& corner_at, Index boundary_size, Index i, Index j);

}  // namespace stripweave
