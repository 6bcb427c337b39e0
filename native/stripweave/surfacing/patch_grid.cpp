#include "stripweave/surfacing/patch_grid.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

namespace {

// The longest control row along u (d = 0) or v (d = 1).
double control_length(const BSplinePatch& p, int d) {
  double longest = 0;
  const int outer = d == 0 ? p.cols() : p.rows(), inner = d == 0 ? p.rows() : p.cols();
  for (int a = 0; a < outer; ++a) {
    double l = 0;
    for (int b = 0; b + 1 < inner; ++b)
      l += d == 0 ? (p.P(b + 1, a) - p.P(b, a)).norm() : (p.P(a, b + 1) - p.P(a, b)).norm();
    longest = std::max(longest, l);
  }
  return longest;
}

// The basis on `spans` spans at each of `t`.
std::vector<CubicBasis> basis_at(int spans, const std::vector<double>& t) {
  std::vector<CubicBasis> out;
  out.reserve(t.size());
  for (double x : t) out.push_back(cubic_basis_at(spans, x));
  return out;
}

// The parameters of a grid of n cells in one direction: its nodes k / n, and
// those of its triangles' centroids, each the mean of three nodes' summed in
// the order the triangle lists them (add(), below), so that it is to the bit
// the parameter the nodes' (u, v) give: of nodes k, k + 1, k + 1 (next2),
// k, k + 1, k (back) and k, k, k + 1 (twice).
struct GridParameters {
  std::vector<double> node, next2, back, twice;
};

GridParameters grid_parameters(int n) {
  GridParameters g;
  const double d = 1.0 / n;
  for (int k = 0; k <= n; ++k) g.node.push_back(k * d);
  for (int k = 0; k < n; ++k) {
    const double a = g.node[k], b = g.node[k + 1];
    g.next2.push_back((a + b + b) / 3);
    g.back.push_back((a + b + a) / 3);
    g.twice.push_back((a + a + b) / 3);
  }
  return g;
}

// mesh: also the triangles, and max_chord measured over them; else the nodes
// only. The basis is evaluated once per grid row and column (the nodes and
// the centroids share their u along a row, their v along a column), which
// was most of a grid's time.
PatchGrid grid_of(const BSplinePatch& patch, int nu, int nv, bool mesh) {
  PatchGrid g;
  g.nu = nu, g.nv = nv;
  const double du = 1.0 / nu, dv = 1.0 / nv;
  const GridParameters pu = grid_parameters(nu), pv = grid_parameters(nv);
  const std::vector<CubicBasis> bu = basis_at(patch.nu, pu.node), bv = basis_at(patch.nv, pv.node);
  const size_t nodes = size_t(nu + 1) * size_t(nv + 1);
  g.uv.reserve(nodes), g.points.reserve(nodes), g.weight.reserve(nodes);
  if (mesh) g.triangles.reserve(2 * size_t(nu) * size_t(nv));
  for (int i = 0; i <= nu; ++i)
    for (int j = 0; j <= nv; ++j) {
      Vec3 S, Su, Sv;
      patch.evaluate(bu[i], bv[j], &S, &Su, &Sv);
      const double ci = (i == 0 || i == nu) ? 0.5 : 1.0, cj = (j == 0 || j == nv) ? 0.5 : 1.0;
      g.uv.emplace_back(pu.node[i], pv.node[j]);
      g.points.push_back(S);
      g.weight.push_back(Su.cross(Sv).norm() * du * dv * ci * cj);
    }
  if (!mesh) return g;
  const std::vector<CubicBasis> u_next2 = basis_at(patch.nu, pu.next2), u_back = basis_at(patch.nu, pu.back);
  const std::vector<CubicBasis> v_next2 = basis_at(patch.nv, pv.next2), v_twice = basis_at(patch.nv, pv.twice);
  auto id = [nv](int i, int j) { return Index(i * (nv + 1) + j); };
  // Triangle (a, b, c) and the basis at its centroid's u and v.
  auto add = [&](Index a, Index b, Index c, const CubicBasis& cu, const CubicBasis& cv) {
    g.triangles.push_back({a, b, c});
    const Vec3 flat = (g.points[a] + g.points[b] + g.points[c]) / 3;
    Vec3 at;
    patch.evaluate(cu, cv, &at, nullptr, nullptr);
    g.max_chord = std::max(g.max_chord, (at - flat).norm());
  };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      // (i, j), (i + 1, j), (i + 1, j + 1): u of nodes i, i + 1, i + 1; v of j, j, j + 1.
      add(id(i, j), id(i + 1, j), id(i + 1, j + 1), u_next2[i], v_twice[j]);
      // (i, j), (i + 1, j + 1), (i, j + 1): u of i, i + 1, i; v of j, j + 1, j + 1.
      add(id(i, j), id(i + 1, j + 1), id(i, j + 1), u_back[i], v_next2[j]);
    }
  return g;
}

// The cell counts along u and v for `per_span` samples per span and at most
// `spacing` between them (before any chordal refinement).
std::array<int, 2> sample_cells(const BSplinePatch& patch, double spacing, int per_span) {
  auto count = [&](int spans, int d) {
    double n = per_span * spans;
    if (spacing > 0) {
      const double length = control_length(patch, d);
      n = std::max(n, std::ceil(length / spacing));
    }
    return std::clamp(static_cast<int>(n), 1, kMaxGridSamples);
  };
  return {count(patch.nu, 0), count(patch.nv, 1)};
}

}  // namespace

PatchGrid patch_grid(const BSplinePatch& patch, double spacing, double chord, int per_span) {
  auto [nu, nv] = sample_cells(patch, spacing, per_span);
  PatchGrid g = grid_of(patch, nu, nv, true);
  for (int round = 0; round < 3 && chord > 0 && g.max_chord > chord && (nu < kMaxGridSamples || nv < kMaxGridSamples); ++round) {
    const double grow = 1.1 * std::sqrt(g.max_chord / chord);
    nu = std::min(kMaxGridSamples, std::max(nu + 1, static_cast<int>(std::ceil(nu * grow))));
    nv = std::min(kMaxGridSamples, std::max(nv + 1, static_cast<int>(std::ceil(nv * grow))));
    g = grid_of(patch, nu, nv, true);
  }
  return g;
}

PatchGrid patch_sample_grid(const BSplinePatch& patch, double spacing, int per_span) {
  const auto [nu, nv] = sample_cells(patch, spacing, per_span);
  return grid_of(patch, nu, nv, false);
}

PatchGrid patch_grid_of_size(const BSplinePatch& patch, int nu, int nv) {
  return grid_of(patch, std::max(nu, 1), std::max(nv, 1), true);
}

}  // namespace stripweave
