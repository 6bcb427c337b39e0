#include "stripweave/surfacing/patch_parameterization.h"

#include "stripweave/core/error.h"
#include "stripweave/surfacing/bspline.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace stripweave {

namespace {

// The boundary loop as a successor map: a boundary half-edge a -> b of a
// counter-clockwise triangle has the patch on its left, so following next[]
// walks the boundary counter-clockwise.
std::vector<Index> boundary_successors(const TriangleMesh& m) {
  std::map<std::pair<Index, Index>, int> half_edges;
  for (const Tri& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++half_edges[{t[k], t[(k + 1) % 3]}];
  std::vector<Index> next(m.num_vertices(), kInvalid);
  for (const auto& [he, count] : half_edges) {
    if (half_edges.count({he.second, he.first})) continue;
    if (next[he.first] != kInvalid)
      throw InputError("patch mesh is not a disc: its boundary touches itself at a vertex");
    next[he.first] = he.second;
  }
  return next;
}

// Step 1: pin the boundary. Corner i goes to square corner i, the vertices
// of side i between by normalized arc length. Returns per vertex whether it
// is pinned; fills out.side_vertices, out.side_t and the boundary's uv.
std::vector<bool> pin_boundary(const NetworkPatch& patch, PatchParameterization& out) {
  const TriangleMesh& m = patch.mesh;
  const Index nv = m.num_vertices();
  const std::vector<Index> next = boundary_successors(m);

  // Walk the boundary from corner 0; the corners must come in order 0,1,2,3.
  out.uv.assign(nv, Vec2::Zero());
  std::vector<bool> fixed(nv, false);
  Index v = patch.corners[0];
  Index steps = 0;
  for (int side = 0; side < 4; ++side) {
    const Index end = patch.corners[(side + 1) % 4];
    auto& verts = out.side_vertices[side];
    verts.push_back(v);
    do {
      if (v == kInvalid || next[v] == kInvalid || ++steps > nv)
        throw InputError("patch mesh boundary is not one loop through its 4 corners in counter-clockwise order");
      v = next[v];
      verts.push_back(v);
      for (int c = 0; c < 4; ++c)
        if (v == patch.corners[c] && v != end)
          throw InputError("patch corners are not in counter-clockwise order along the patch boundary");
    } while (v != end);
    // Normalized arc length along the side.
    auto& t = out.side_t[side];
    t.assign(verts.size(), 0.0);
    for (size_t k = 1; k < verts.size(); ++k)
      t[k] = t[k - 1] + (m.positions[verts[k]] - m.positions[verts[k - 1]]).norm();
    if (t.back() <= 0) throw InputError("patch side has zero length");
    for (double& x : t) x /= t.back();
    for (size_t k = 0; k < verts.size(); ++k) {
      out.uv[verts[k]] = side_uv(side, t[k]);
      fixed[verts[k]] = true;
    }
  }
  // A boundary vertex not on the walk means more than one boundary loop.
  for (Index w = 0; w < nv; ++w)
    if (next[w] != kInvalid && !fixed[w])
      throw InputError("patch mesh is not a disc: it has more than one boundary loop");
  return fixed;
}

// Step 2: cotangent weights per undirected edge, clamped below (see header).
std::map<EdgeKey, double> clamped_cotangent_weights(const TriangleMesh& m) {
  std::map<EdgeKey, double> weight;
  double total = 0;
  for (const Tri& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const Vec3& a = m.positions[t[k]];
      const Vec3& b = m.positions[t[(k + 1) % 3]];
      const Vec3& c = m.positions[t[(k + 2) % 3]];
      const Vec3 e1 = a - c, e2 = b - c;
      const double cross = e1.cross(e2).norm();
      const double cot = cross > 1e-300 ? e1.dot(e2) / cross : 0.0;
      weight[edge_key(t[k], t[(k + 1) % 3])] += 0.5 * cot;
      total += 0.5 * std::abs(cot);
    }
  const double floor_w = 1e-3 * std::max(total / std::max<size_t>(weight.size(), 1), 1e-12);
  for (auto& [e, w] : weight) w = std::max(w, floor_w);
  return weight;
}

// Step 3: the interior as the convex-combination map of the edge weights,
// one sparse Cholesky solve for u and v. The matrix's pattern is the mesh's,
// whatever the weights, so `solver` is analysed once and refactorized.
class InteriorSolve {
 public:
  InteriorSolve(const std::vector<bool>& fixed) : fixed_(fixed), free_id_(fixed.size(), kInvalid) {
    for (size_t w = 0; w < fixed.size(); ++w)
      if (!fixed[w]) free_id_[w] = nfree_++;
  }
  Index num_free() const { return nfree_; }

  // uv of the free vertices from the pinned ones' uv and the weights.
  void solve(const std::map<EdgeKey, double>& weight, std::vector<Vec2>& uv) {
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nfree_, 2);
    std::vector<double> diag(nfree_, 0.0);
    for (const auto& [e, w] : weight)
      for (int s = 0; s < 2; ++s) {
        const Index i = e[s], j = e[1 - s];
        if (fixed_[i]) continue;
        diag[free_id_[i]] += w;
        if (fixed_[j])
          rhs.row(free_id_[i]) += w * uv[j].transpose();
        else
          trip.emplace_back(free_id_[i], free_id_[j], -w);
      }
    for (Index i = 0; i < nfree_; ++i) trip.emplace_back(i, i, diag[i]);
    Eigen::SparseMatrix<double> L(nfree_, nfree_);
    L.setFromTriplets(trip.begin(), trip.end());
    if (!analysed_) solver_.analyzePattern(L), analysed_ = true;
    solver_.factorize(L);
    if (solver_.info() != Eigen::Success)
      throw InputError("patch parameterization failed: an interior part of the patch mesh is not connected to its boundary");
    const Eigen::MatrixXd x = solver_.solve(rhs);
    for (size_t w = 0; w < fixed_.size(); ++w)
      if (!fixed_[w]) uv[w] = x.row(free_id_[w]).transpose().cwiseMax(0.0).cwiseMin(1.0);
  }

 private:
  const std::vector<bool>& fixed_;
  std::vector<Index> free_id_;
  Index nfree_ = 0;
  bool analysed_ = false;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
};

// Per triangle its L2 stretch (Sander et al. 2001) of the map from the
// square onto the surface, sqrt((Gamma^2 + gamma^2) / 2), scaled so that a
// map with the patch's area spread evenly over the square has stretch 1
// everywhere. A triangle the map squashed to (almost) nothing gets
// kMaxStretch, not infinity.
constexpr double kMaxStretch = 1e3;

struct MapStretch {
  std::vector<double> triangle;  // per triangle
  std::vector<double> area;      // per triangle, on the part
  double l2 = 0;                 // over the patch, weighted by surface area
};

MapStretch map_stretch(const TriangleMesh& m, const std::vector<Vec2>& uv) {
  MapStretch s;
  s.triangle.resize(m.triangles.size());
  std::vector<double>& area = s.area;
  area.resize(m.triangles.size());
  double area_3d = 0;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const Tri& f = m.triangles[t];
    const Vec3 &q1 = m.positions[f[0]], &q2 = m.positions[f[1]], &q3 = m.positions[f[2]];
    const Vec2 &p1 = uv[f[0]], &p2 = uv[f[1]], &p3 = uv[f[2]];
    area[t] = 0.5 * (q2 - q1).cross(q3 - q1).norm();
    area_3d += area[t];
    const double a2 = 0.5 * ((p2.x() - p1.x()) * (p3.y() - p1.y()) - (p3.x() - p1.x()) * (p2.y() - p1.y()));
    if (std::abs(a2) <= 1e-300) {
      s.triangle[t] = kMaxStretch;
      continue;
    }
    // The map's partial derivatives over the triangle.
    const Vec3 Ss = (q1 * (p2.y() - p3.y()) + q2 * (p3.y() - p1.y()) + q3 * (p1.y() - p2.y())) / (2 * a2);
    const Vec3 St = (q1 * (p3.x() - p2.x()) + q2 * (p1.x() - p3.x()) + q3 * (p2.x() - p1.x())) / (2 * a2);
    s.triangle[t] = std::sqrt(0.5 * (Ss.squaredNorm() + St.squaredNorm()));
  }
  if (area_3d <= 0) return s;
  const double unit = 1 / std::sqrt(area_3d);  // the square's area is 1
  double sum = 0;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    s.triangle[t] = std::min(s.triangle[t] * unit, kMaxStretch);
    sum += area[t] * s.triangle[t] * s.triangle[t];
  }
  s.l2 = std::sqrt(sum / area_3d);
  return s;
}

// Step 4, for a patch with NetworkPatch::even_stretch: equalize the
// stretch (Yoshizawa, Belyaev and Seidel 2004, with symmetric edge
// weights). A harmonic map shrinks a protrusion of the patch (a boss, a
// knob, a deep dimple) exponentially in its height, and a B-spline with
// evenly spaced knots cannot resolve what the square holds in a speck.
// Each round divides every edge's weight by its stretch (the RMS over its
// triangles): a squashed region becomes cheaper to spread and grows. The
// weights stay positive, so each map is still a bijection. The rounds go
// on while the patch's L2 stretch falls by a clear margin, and the map of
// least stretch is kept.
constexpr int kStretchRounds = 10;
constexpr double kStretchGain = 0.99;  // a round must lower the L2 stretch by 1 %

void equalize_stretch(const TriangleMesh& m, InteriorSolve& interior, std::map<EdgeKey, double> weight,
                      std::vector<Vec2>& uv) {
  MapStretch best = map_stretch(m, uv);
  std::vector<Vec2> trial = uv;
  for (int round = 0; round < kStretchRounds; ++round) {
    std::map<EdgeKey, std::pair<double, int>> edge_stretch;  // sum of squares, triangles
    for (size_t t = 0; t < m.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        auto& e = edge_stretch[edge_key(m.triangles[t][k], m.triangles[t][(k + 1) % 3])];
        e.first += best.triangle[t] * best.triangle[t];
        ++e.second;
      }
    for (auto& [e, w] : weight) {
      const auto& [sq, n] = edge_stretch[e];
      w /= std::clamp(std::sqrt(sq / std::max(n, 1)), 1 / kMaxStretch, kMaxStretch);
    }
    interior.solve(weight, trial);
    MapStretch s = map_stretch(m, trial);
    if (!(s.l2 < kStretchGain * best.l2)) break;
    uv = trial;
    best = std::move(s);
  }
}

// The largest per-vertex L2 stretch of a map (even_map_gain).
double max_vertex_stretch(const TriangleMesh& m, const std::vector<Vec2>& uv) {
  const MapStretch s = map_stretch(m, uv);
  std::vector<double> sum(m.num_vertices(), 0.0), area(m.num_vertices(), 0.0);
  for (size_t t = 0; t < m.triangles.size(); ++t)
    for (Index v : m.triangles[t]) sum[v] += s.area[t] * s.triangle[t] * s.triangle[t], area[v] += s.area[t];
  double worst = 0;
  for (Index v = 0; v < m.num_vertices(); ++v)
    if (area[v] > 0) worst = std::max(worst, std::sqrt(sum[v] / area[v]));
  return worst;
}


// Steps 1 to 3 (the harmonic map); `even`: step 4 too. `harmonic_stretch`,
// when given, gets the harmonic map's largest per-vertex stretch.
PatchParameterization map_onto_square(const NetworkPatch& patch, bool even, double* harmonic_stretch = nullptr) {
  const TriangleMesh& m = patch.mesh;
  PatchParameterization out = square_sides(patch);
  std::vector<bool> fixed(m.num_vertices(), false);
  for (const auto& side : out.side_vertices)
    for (Index v : side) fixed[v] = true;
  InteriorSolve interior(fixed);
  if (interior.num_free() > 0) {
    const std::map<EdgeKey, double> weight = clamped_cotangent_weights(m);
    interior.solve(weight, out.uv);
    if (harmonic_stretch) *harmonic_stretch = max_vertex_stretch(m, out.uv);
    if (even) equalize_stretch(m, interior, weight, out.uv);
  } else if (harmonic_stretch) {
    *harmonic_stretch = max_vertex_stretch(m, out.uv);
  }
  return out;
}

}  // namespace

PatchParameterization square_sides(const NetworkPatch& patch) {
  const TriangleMesh& m = patch.mesh;
  if (m.num_triangles() == 0) throw InputError("patch has an empty triangle mesh");
  for (Index c : patch.corners)
    if (c < 0 || c >= m.num_vertices()) throw InputError("patch corner is not a vertex of its mesh");
  PatchParameterization out;
  pin_boundary(patch, out);
  return out;
}

PatchParameterization square_map(const NetworkPatch& patch) { return map_onto_square(patch, patch.even_stretch); }

double even_map_gain(const NetworkPatch& patch) {
  double harmonic = 0;
  const PatchParameterization even = map_onto_square(patch, true, &harmonic);
  const double after = max_vertex_stretch(patch.mesh, even.uv);
  return after > 0 ? harmonic / after : 1.0;
}

}  // namespace stripweave
