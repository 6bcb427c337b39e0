// Triangulating one polygonal face of a mesh file (OBJ, OFF n-gons).
//
// triangulate_polygon(positions, corners, out) -> false if the polygon is not
//   simple (two of its edges that are not neighbours meet, in the plane of
//   its Newell normal), else appends its triangles, in the corners' winding,
//   to `out`.
// Ear clipping in the plane of the polygon's Newell normal: a concave n-gon
// becomes triangles that cover it exactly (a fan from the first corner folded
// caps over its notches). Quadratic in the corner count; the readers bound it
// with kMaxPolygonCorners.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

namespace stripweave {

constexpr std::size_t kMaxPolygonCorners = 4096;

bool triangulate_polygon(const std::vector<Vec3>& positions, const std::vector<Index>& corners, std::vector<Tri>& out);

}  // namespace stripweave
