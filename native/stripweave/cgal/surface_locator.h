// SurfaceLocator: nearest points on a triangle mesh (CGAL AABB tree adapter).
//
// Built once per mesh; answers closest-point queries in O(log n). Used to
// project anchors onto the surface (§5.4) and, later, to pick under the
// cursor.
//   closest(p) -> {point on the mesh, triangle id, barycentric coordinates,
//                 distance}
//   closest(p, hint) -> the same, the search started from a previous answer
//                 (much faster for queries in spatial order: the hint bounds
//                 the search instead of a nearest-neighbour lookup; the
//                 answer is the same nearest point, up to ties)
//   InputError for a point with a coordinate not finite or beyond
//   kMaxQueryCoordinate (the mesh's own units): farther points overflow.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

#include <memory>

namespace stripweave {

struct SurfacePoint3 {
  Vec3 point = Vec3::Zero();
  Index triangle = kInvalid;
  Vec3 barycentric = Vec3::Zero();
  double distance = 0;
};

constexpr double kMaxQueryCoordinate = 1e100;

class SurfaceLocator {
 public:
  // accelerate: a k-d tree of the triangles' reference points answers a
  // query without a hint (CGAL's accelerate_distance_queries, some 40 bytes
  // a triangle); without it a query without a hint starts from an arbitrary
  // triangle (slower, the same answer), which suits callers that pass hints.
  explicit SurfaceLocator(const TriangleMesh& mesh, bool accelerate = true);
  ~SurfaceLocator();
  SurfacePoint3 closest(const Vec3& p) const;
  SurfacePoint3 closest(const Vec3& p, const SurfacePoint3& hint) const;

 private:
  struct Impl;
  SurfacePoint3 answer(const Vec3& p, const Vec3& q, Index triangle) const;
  std::unique_ptr<Impl> impl_;
};

}  // namespace stripweave
