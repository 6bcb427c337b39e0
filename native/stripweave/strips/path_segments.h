// The pieces of an embedded loop inside each triangle it crosses.
//
// path_segments(surface, path, closed) -> std::vector<PathSegment>
//   Consecutive points of a SurfacePath (embed_path.h) lie on the boundary of
//   a common triangle (on its edges or at its corners). Each segment names
//   that triangle, the two path points (indices into path.points, the second
//   wrapping to 0 for the closing segment of a closed path), and the unit
//   direction of travel. Zero-length steps (a point repeated) are skipped.
//   Where two triangles contain both points (the step runs along a mesh
//   edge), the one on the left of the travel direction is taken.
// Used by the cross field (a loop constrains the triangles it crosses, §6.1)
// and by the parameterization (the loop is an isocurve there).
#pragma once

#include "stripweave/elastica/embed_path.h"

namespace stripweave {

struct PathSegment {
  Index triangle = kInvalid;
  Index from = kInvalid, to = kInvalid;  // indices into path.points
  Vec3 direction = Vec3::Zero();         // unit, (to - from) normalized
};

std::vector<PathSegment> path_segments(const Surface& surface, const SurfacePath& path, bool closed);

// The barycentric coordinates of path point i in triangle t (corners in
// mesh order). The point is a corner of t or lies on one of t's edges.
Vec3 barycentric_in(const Surface& surface, const SurfacePath& path, Index i, Index t);

}  // namespace stripweave
