#include "stripweave/surfacing/patch_parameterization.h"

#include "stripweave/core/error.h"
#include "stripweave/surfacing/bspline.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
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

}  // namespace

PatchParameterization harmonic_square_map(const NetworkPatch& patch) {
  const TriangleMesh& m = patch.mesh;
  const Index nv = m.num_vertices();
  if (m.num_triangles() == 0) throw InputError("patch has an empty triangle mesh");
  for (Index c : patch.corners)
    if (c < 0 || c >= nv) throw InputError("patch corner is not a vertex of its mesh");

  const std::vector<Index> next = boundary_successors(m);

  // Walk the boundary from corner 0; the corners must come in order 0,1,2,3.
  PatchParameterization out;
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

  // Free (interior) vertices in a compact numbering.
  std::vector<Index> free_id(nv, kInvalid);
  Index nfree = 0;
  for (Index w = 0; w < nv; ++w)
    if (!fixed[w]) free_id[w] = nfree++;
  if (nfree == 0) return out;

  // Cotangent weights per undirected edge, clamped below (see header).
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

  std::vector<Eigen::Triplet<double>> trip;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nfree, 2);
  std::vector<double> diag(nfree, 0.0);
  for (const auto& [e, w0] : weight) {
    const double w = std::max(w0, floor_w);
    for (int s = 0; s < 2; ++s) {
      const Index i = e[s], j = e[1 - s];
      if (fixed[i]) continue;
      diag[free_id[i]] += w;
      if (fixed[j])
        rhs.row(free_id[i]) += w * out.uv[j].transpose();
      else
        trip.emplace_back(free_id[i], free_id[j], -w);
    }
  }
  for (Index i = 0; i < nfree; ++i) trip.emplace_back(i, i, diag[i]);
  Eigen::SparseMatrix<double> L(nfree, nfree);
  L.setFromTriplets(trip.begin(), trip.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(L);
  if (solver.info() != Eigen::Success)
    throw InputError("patch parameterization failed: an interior part of the patch mesh is not connected to its boundary");
  const Eigen::MatrixXd x = solver.solve(rhs);
  for (Index w = 0; w < nv; ++w)
    if (!fixed[w]) out.uv[w] = x.row(free_id[w]).transpose().cwiseMax(0.0).cwiseMin(1.0);
  return out;
}

}  // namespace stripweave
