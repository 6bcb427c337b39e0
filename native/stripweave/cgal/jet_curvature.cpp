// Principal curvatures by jet fitting (CGAL Monge_via_jet_fitting).
//
// Per vertex: gather a mesh-connected neighbourhood, fit a height-function jet
// in its PCA frame, read curvatures and directions off the Monge form, and
// convert CGAL's sign convention to ours.
#include "stripweave/cgal/jet_curvature.h"

// Monge_via_jet_fitting only has a default SVD (Eigen_svd) under this flag,
// and it must be the same in every CGAL translation unit (one definition rule).
#include <CGAL/Eigen_svd.h>
#include <CGAL/Monge_via_jet_fitting.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <utility>
#include <vector>

namespace stripweave {
namespace {

// The fit works in doubles internally whatever the data kernel; a plain
// Cartesian kernel avoids needless conversions (and compile time).
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Fitter = CGAL::Monge_via_jet_fitting<Kernel, Kernel, CGAL::Eigen_svd>;

// Degree 2: its 6 coefficients are well determined by the 16+ points we use.
// A quartic needs 15 and, measured on spheres and tori with these
// neighbourhoods, is ill-conditioned (curvature errors of 4% to several 100%
// where the quadric stays under 2%) and five times slower.
constexpr std::size_t kJetDegree = 2;
constexpr std::size_t kMongeDegree = 2;
constexpr std::size_t kMinFitPoints = (kJetDegree + 1) * (kJetDegree + 2) / 2;

// Vertex adjacency in compressed rows: neighbours of v are
// neighbour[offset[v] .. offset[v+1]).
struct Adjacency {
  std::vector<Index> offset;
  std::vector<Index> neighbour;
};

Adjacency build_adjacency(const TriangleMesh& mesh) {
  const std::size_t nv = mesh.positions.size();
  std::vector<Index> degree(nv + 1, 0);
  for (const Tri& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) degree[t[k]] += 2;  // both edges at each corner
  Adjacency adj;
  adj.offset.assign(nv + 1, 0);
  for (std::size_t v = 0; v < nv; ++v) adj.offset[v + 1] = adj.offset[v] + degree[v];
  adj.neighbour.resize(adj.offset[nv]);
  std::vector<Index> fill(adj.offset.begin(), adj.offset.end() - 1);
  for (const Tri& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Index a = t[k], b = t[(k + 1) % 3];
      adj.neighbour[fill[a]++] = b;
      adj.neighbour[fill[b]++] = a;
    }
  }
  // Each interior edge was entered twice; compact the duplicates away.
  Index write = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    auto first = adj.neighbour.begin() + adj.offset[v];
    auto last = adj.neighbour.begin() + adj.offset[v + 1];
    std::sort(first, last);
    last = std::unique(first, last);
    adj.offset[v] = write;
    for (auto it = first; it != last; ++it) adj.neighbour[write++] = *it;
  }
  adj.offset[nv] = write;
  adj.neighbour.resize(write);
  return adj;
}

std::vector<Vec3> area_weighted_normals(const TriangleMesh& mesh) {
  std::vector<Vec3> n(mesh.positions.size(), Vec3::Zero());
  for (Index t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3 a2 = triangle_normal_area2(mesh, t);  // |a2| = twice the area
    for (Index v : mesh.triangles[t]) n[v] += a2;
  }
  return n;
}

// Best-first growth from the centre vertex, ordered by Euclidean distance to
// it and moving only along mesh edges. Every vertex of the ball that the ball
// connects to the centre comes out before any vertex outside it, so "take all
// within the radius, then the nearest ones beyond until there are enough" is
// the ring growth the contract asks for, without the bias of whole rings.
// Growth stops at vertices facing away from the centre (normals more than 90
// degrees apart): on a part thinner than the radius the walk would otherwise
// turn round the rim onto the other side, which no height function can fit.
class NeighbourhoodGrower {
 public:
  NeighbourhoodGrower(const TriangleMesh& mesh, const Adjacency& adj, const std::vector<Vec3>& normals)
      : mesh_(mesh), adj_(adj), normals_(normals), stamp_(mesh.positions.size(), 0) {}

  // Fills `out` with the centre first (the jet's origin is its first point).
  void gather(Index centre, double radius, std::size_t min_count, std::vector<Index>& out) {
    out.clear();
    ++epoch_;
    heap_ = Heap();
    const Vec3& c = mesh_.positions[centre];
    const Vec3& nc = normals_[centre];
    const bool oriented = nc.squaredNorm() > 0.0;
    const double r2 = radius * radius;
    stamp_[centre] = epoch_;
    heap_.emplace(0.0, centre);
    while (!heap_.empty()) {
      const auto [d2, u] = heap_.top();
      if (d2 > r2 && out.size() >= min_count) break;
      heap_.pop();
      out.push_back(u);
      for (Index k = adj_.offset[u]; k < adj_.offset[u + 1]; ++k) {
        const Index w = adj_.neighbour[k];
        if (stamp_[w] == epoch_) continue;
        stamp_[w] = epoch_;
        if (oriented && normals_[w].dot(nc) <= 0.0) continue;
        heap_.emplace((mesh_.positions[w] - c).squaredNorm(), w);
      }
    }
  }

 private:
  using Entry = std::pair<double, Index>;
  using Heap = std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>>;
  const TriangleMesh& mesh_;
  const Adjacency& adj_;
  const std::vector<Vec3>& normals_;  // area-weighted, not normalised
  std::vector<unsigned> stamp_;  // visited marks without clearing per vertex
  unsigned epoch_ = 0;
  Heap heap_;
};

struct LocalCurvature {
  Vec3 normal, d_min, d_max;
  double k_min = 0.0, k_max = 0.0;
};

Vec3 to_vec(const Kernel::Vector_3& v) { return Vec3(v.x(), v.y(), v.z()); }

// Fits the jet and converts the Monge form. Returns false when the fit cannot
// be trusted: too few points, a singular system, or a fitted normal that
// disagrees with the mesh (the neighbourhood folded over, so the PCA frame
// is not a height-function frame).
bool fit(Fitter& fitter, const std::vector<Point>& pts, const Vec3& mesh_normal, LocalCurvature& out) {
  if (pts.size() < kMinFitPoints) return false;
  Fitter::Monge_form monge = fitter(pts.begin(), pts.end(), kJetDegree, kMongeDegree);
  if (!std::isfinite(fitter.condition_number()) || fitter.condition_number() > 1e10) return false;

  const bool has_mesh_normal = mesh_normal.squaredNorm() > 0.0;
  if (has_mesh_normal) monge.comply_wrt_given_normal(Kernel::Vector_3(mesh_normal.x(), mesh_normal.y(), mesh_normal.z()));

  Vec3 n = to_vec(monge.normal_direction());
  Vec3 d1 = to_vec(monge.maximal_principal_direction());  // CGAL's k1 >= k2
  Vec3 d2 = to_vec(monge.minimal_principal_direction());
  const double k1 = monge.principal_curvatures(0), k2 = monge.principal_curvatures(1);
  if (!n.allFinite() || !d1.allFinite() || !d2.allFinite() || !std::isfinite(k1) || !std::isfinite(k2)) return false;
  if (n.squaredNorm() == 0.0) return false;
  n.normalize();
  // More than ~75 degrees between fitted and mesh normal: not a surface patch
  // seen from above, whatever the numbers say.
  if (has_mesh_normal && n.dot(mesh_normal.normalized()) < 0.25) return false;

  // CGAL's Monge form is z = (k1 x^2 + k2 y^2) / 2 along its normal, so a
  // surface bending away from the (outward) normal has negative k. Ours is
  // positive there: negate, which also swaps which one is the larger.
  d1 -= d1.dot(n) * n;
  d2 -= d2.dot(n) * n;
  if (d1.squaredNorm() == 0.0 || d2.squaredNorm() == 0.0) return false;
  out.normal = n;
  out.k_min = -k1;
  out.d_min = d1.normalized();
  out.k_max = -k2;
  out.d_max = d2.normalized();
  return true;
}

// Last resort for a vertex no neighbourhood can fit (an isolated vertex or a
// component of a few vertices): flat, with the mesh normal and any tangent
// frame, so the output never holds NaN.
LocalCurvature flat_frame(const Vec3& mesh_normal) {
  LocalCurvature c;
  c.normal = mesh_normal.squaredNorm() > 0.0 ? mesh_normal.normalized() : Vec3::UnitZ();
  const Vec3 helper = std::abs(c.normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  c.d_min = c.normal.cross(helper).normalized();
  c.d_max = c.normal.cross(c.d_min);
  return c;
}

}  // namespace

CurvatureField jet_fit_curvature(const TriangleMesh& mesh, double radius, int min_neighbours) {
  const Index nv = mesh.num_vertices();
  CurvatureField field;
  field.normal.resize(nv);
  field.k_min.resize(nv);
  field.k_max.resize(nv);
  field.d_min.resize(nv);
  field.d_max.resize(nv);

  const Adjacency adj = build_adjacency(mesh);
  const std::vector<Vec3> mesh_normal = area_weighted_normals(mesh);
  NeighbourhoodGrower grower(mesh, adj, mesh_normal);
  Fitter fitter;
  std::vector<Index> ids;
  std::vector<Point> pts;
  const std::size_t base_count = std::max<std::size_t>(kMinFitPoints, min_neighbours > 0 ? min_neighbours : 0);
  const double base_radius = std::isfinite(radius) && radius > 0.0 ? radius : 0.0;

  // A failed fit is retried on larger neighbourhoods, where degeneracies
  // (collinear rings, too few points) go away; then on the tightest one a
  // quadric allows, for a fold or tip that only looks like a height function
  // from very close.
  struct Neighbourhood {
    double radius;
    std::size_t count;
  };
  const Neighbourhood attempts[] = {{base_radius, base_count},
                                    {2.0 * base_radius, 2 * base_count},
                                    {4.0 * base_radius, 4 * base_count},
                                    {0.0, kMinFitPoints + 4}};

  for (Index v = 0; v < nv; ++v) {
    LocalCurvature c;
    bool ok = false;
    for (const Neighbourhood& hood : attempts) {
      grower.gather(v, hood.radius, hood.count, ids);
      pts.clear();
      for (Index u : ids) {
        const Vec3& p = mesh.positions[u];
        pts.emplace_back(p.x(), p.y(), p.z());
      }
      if ((ok = fit(fitter, pts, mesh_normal[v], c))) break;
    }
    if (!ok) c = flat_frame(mesh_normal[v]);
    field.normal[v] = c.normal;
    field.k_min[v] = c.k_min;
    field.k_max[v] = c.k_max;
    field.d_min[v] = c.d_min;
    field.d_max[v] = c.d_max;
  }
  return field;
}

}  // namespace stripweave
