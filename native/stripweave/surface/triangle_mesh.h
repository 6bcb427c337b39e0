// TriangleMesh: the plain indexed triangle mesh every stage exchanges.
//
//   positions[v]  : vertex position
//   triangles[t]  : three vertex indices, counter-clockwise seen from outside
//
// No connectivity is stored here; `MeshTopology` derives it. A TriangleMesh
// read from a file may still be a "soup" (duplicates, degenerate or
// non-manifold triangles); `sanitize_mesh` turns it into a clean one.
#pragma once

#include "stripweave/core/types.h"

namespace stripweave {

struct TriangleMesh {
  std::vector<Vec3> positions;  // per vertex
  std::vector<Tri> triangles;   // per triangle

  Index num_vertices() const { return static_cast<Index>(positions.size()); }
  Index num_triangles() const { return static_cast<Index>(triangles.size()); }
};

// Axis-aligned bounding box of the vertices.
struct BoundingBox {
  Vec3 min = Vec3::Constant(1e300);
  Vec3 max = Vec3::Constant(-1e300);
  void add(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  double diagonal() const { return (max - min).norm(); }
  Vec3 center() const { return 0.5 * (min + max); }
};

inline BoundingBox bounding_box(const std::vector<Vec3>& points) {
  BoundingBox box;
  for (const Vec3& p : points) box.add(p);
  return box;
}

inline Vec3 triangle_normal_area2(const TriangleMesh& m, Index t) {
  const Tri& f = m.triangles[t];
  return (m.positions[f[1]] - m.positions[f[0]]).cross(m.positions[f[2]] - m.positions[f[0]]);
}

}  // namespace stripweave
