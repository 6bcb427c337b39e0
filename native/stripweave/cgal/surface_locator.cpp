#include "stripweave/cgal/surface_locator.h"

#include "stripweave/core/error.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace stripweave {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point to_point(const Vec3& p) { return Point(p.x(), p.y(), p.z()); }
}  // namespace

struct SurfaceLocator::Impl {
  const TriangleMesh& mesh;
  std::vector<Triangle> triangles;  // the tree refers to these by iterator
  Tree tree;
  explicit Impl(const TriangleMesh& m) : mesh(m) {
    triangles.reserve(m.triangles.size());
    for (const Tri& t : m.triangles)
      triangles.emplace_back(to_point(m.positions[t[0]]), to_point(m.positions[t[1]]), to_point(m.positions[t[2]]));
    tree.insert(triangles.begin(), triangles.end());
    tree.accelerate_distance_queries();
  }
};

SurfaceLocator::SurfaceLocator(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>(mesh)) {}
SurfaceLocator::~SurfaceLocator() = default;

namespace {

// The exact fallback of the filtered kernel turns a double into a GMP
// rational, which raises SIGFPE on an infinity: a point whose squared
// distances overflow must never reach the tree.
void check_query(const Vec3& p) {
  if (!(p.cwiseAbs().maxCoeff() <= kMaxQueryCoordinate))
    throw InputError("a query point is not finite or is too far from the surface to locate");
}

}  // namespace

SurfacePoint3 SurfaceLocator::closest(const Vec3& p) const {
  check_query(p);
  const auto [q, primitive] = impl_->tree.closest_point_and_primitive(to_point(p));
  return answer(p, Vec3(q.x(), q.y(), q.z()), static_cast<Index>(primitive - impl_->triangles.cbegin()));
}

SurfacePoint3 SurfaceLocator::closest(const Vec3& p, const SurfacePoint3& hint) const {
  if (hint.triangle == kInvalid) return closest(p);
  check_query(p);
  const auto [q, primitive] =
      impl_->tree.closest_point_and_primitive(to_point(p), {to_point(hint.point), impl_->triangles.cbegin() + hint.triangle});
  return answer(p, Vec3(q.x(), q.y(), q.z()), static_cast<Index>(primitive - impl_->triangles.cbegin()));
}

SurfacePoint3 SurfaceLocator::answer(const Vec3& p, const Vec3& q, Index triangle) const {
  SurfacePoint3 out;
  out.point = q;
  out.triangle = triangle;
  out.distance = (out.point - p).norm();
  // Barycentric coordinates of q in its triangle (for picking a vertex and
  // for interpolating per-vertex data).
  const Tri& t = impl_->mesh.triangles[out.triangle];
  const Vec3 a = impl_->mesh.positions[t[0]], b = impl_->mesh.positions[t[1]], c = impl_->mesh.positions[t[2]];
  const Vec3 n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  if (area2 > 0) {
    const double u = (c - b).cross(out.point - b).dot(n) / area2;
    const double v = (a - c).cross(out.point - c).dot(n) / area2;
    out.barycentric = Vec3(u, v, 1 - u - v);
  } else {
    out.barycentric = Vec3(1, 0, 0);
  }
  return out;
}

}  // namespace stripweave
