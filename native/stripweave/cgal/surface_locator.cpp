#include "stripweave/cgal/surface_locator.h"

#include "stripweave/core/error.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <boost/iterator/counting_iterator.hpp>

namespace stripweave {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;

Point to_point(const Vec3& p) { return Point(p.x(), p.y(), p.z()); }

// A mesh triangle by its index (CGAL's AABBPrimitiveWithSharedData): the tree
// takes its geometry from the mesh when it needs it. CGAL's triangle primitive
// needs a copy of every triangle (72 bytes each, a third of the tree's memory:
// the fit's deviation locates on a tessellation of a million triangles and
// more); the triangles, their boxes and reference points (the first corner,
// as that primitive's) are the same numbers, so the tree and its answers are.
struct MeshTriangle {
  using Id = Index;
  using Datum = Triangle;
  using Point = Kernel::Point_3;
  using Shared_data = const TriangleMesh*;

  MeshTriangle() = default;
  MeshTriangle(boost::counting_iterator<Index> it, const TriangleMesh*) : id_(*it) {}
  static Shared_data construct_shared_data(const TriangleMesh* mesh) { return mesh; }
  Id id() const { return id_; }
  Datum datum(Shared_data mesh) const {
    const Tri& t = mesh->triangles[id_];
    return Triangle(to_point(mesh->positions[t[0]]), to_point(mesh->positions[t[1]]), to_point(mesh->positions[t[2]]));
  }
  Point reference_point(Shared_data mesh) const { return to_point(mesh->positions[mesh->triangles[id_][0]]); }

 private:
  Index id_ = kInvalid;
};
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, MeshTriangle>>;
}  // namespace

struct SurfaceLocator::Impl {
  const TriangleMesh& mesh;
  Tree tree;
  Impl(const TriangleMesh& m, bool accelerate) : mesh(m) {
    tree.insert(boost::counting_iterator<Index>(0), boost::counting_iterator<Index>(m.num_triangles()), &mesh);
    if (accelerate) tree.accelerate_distance_queries();
    else tree.do_not_accelerate_distance_queries(), tree.build();
  }
};

SurfaceLocator::SurfaceLocator(const TriangleMesh& mesh, bool accelerate)
    : impl_(std::make_unique<Impl>(mesh, accelerate)) {}
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
  return answer(p, Vec3(q.x(), q.y(), q.z()), primitive);
}

SurfacePoint3 SurfaceLocator::closest(const Vec3& p, const SurfacePoint3& hint) const {
  if (hint.triangle == kInvalid) return closest(p);
  check_query(p);
  const auto [q, primitive] = impl_->tree.closest_point_and_primitive(to_point(p), {to_point(hint.point), hint.triangle});
  return answer(p, Vec3(q.x(), q.y(), q.z()), primitive);
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
