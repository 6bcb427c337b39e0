// Strip extraction: the part of the surface a loop "owns" (paper §6.1).
//
// extract_strip(surface, field, param, loops, l) -> Strip
//   Input : the surface, its cross field and global parameterization S (in
//           which every loop is an isocurve), the design's loops, and the
//           index l of the loop whose strip is wanted.
//   Method: the loop is the isocurve "across = 0" of its strip. Starting
//           from the triangles the loop crosses, the adjacent isocurves are
//           conquered on both sides in order of their distance |across|
//           (a Dijkstra over triangles, each carrying the affine map from its
//           chart of S to strip coordinates (along, across), carried on
//           through S's transitions). A side stops at the first isocurve that
//           meets an obstacle: a singularity of the field, a fold-over of S,
//           or a degenerate triangle. It also stops where it meets the other
//           side again (a strip that wraps around the whole surface, e.g. a
//           meridian strip on a torus) and at open boundaries.
//   Output:
//     covered[t]      1 if triangle t belongs to the strip
//     triangles       the covered triangles, in conquest order
//     coords[k][i]    strip coordinates (along, across) of corner i of the
//                     covered triangle triangles[k] (one entry per covered
//                     triangle, not per surface triangle: a design keeps
//                     every strip twice, DesignState), model units: across is the
//                     signed distance from the loop, positive on its left
//                     (normal x direction of travel); along grows with the
//                     loop's direction of travel (on a closed loop it jumps
//                     once, where the conquest meets itself)
//     isocurve[v]     per vertex of the strip, the unit tangent of the strip's
//                     isocurves there (zero outside the strip); the
//                     compatibility mask uses it (§6.2)
//     width_left, width_right   how far the strip reaches on each side
//     stop_left, stop_right     why each side stopped
//     area_fraction   covered area over the surface's area
#pragma once

#include "stripweave/strips/parameterization.h"

#include <string>

namespace stripweave {

struct Strip {
  std::vector<std::uint8_t> covered;
  std::vector<Index> triangles;
  std::vector<std::array<Vec2, 3>> coords;  // parallel to triangles
  std::vector<Vec3> isocurve;
  double width_left = 0, width_right = 0;
  std::string stop_left, stop_right;  // "singularity", "fold-over", "boundary", "wrap", "surface"
  double area_fraction = 0;
};

Strip extract_strip(const Surface& surface, const CrossField& field, const Parameterization& param,
                    const std::vector<LoopPath>& loops, Index l);

}  // namespace stripweave
