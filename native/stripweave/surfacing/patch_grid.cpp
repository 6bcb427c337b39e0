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

// mesh: also the triangles, and max_chord measured over them; else the nodes only.
PatchGrid grid_of(const BSplinePatch& patch, int nu, int nv, bool mesh) {
  PatchGrid g;
  g.nu = nu, g.nv = nv;
  const double du = 1.0 / nu, dv = 1.0 / nv;
  const size_t nodes = size_t(nu + 1) * size_t(nv + 1);
  g.uv.reserve(nodes), g.points.reserve(nodes), g.weight.reserve(nodes);
  if (mesh) g.triangles.reserve(2 * size_t(nu) * size_t(nv));
  for (int i = 0; i <= nu; ++i)
    for (int j = 0; j <= nv; ++j) {
      const Vec2 uv(i * du, j * dv);
      Vec3 S, Su, Sv;
      patch.evaluate(uv.x(), uv.y(), &S, &Su, &Sv);
      const double ci = (i == 0 || i == nu) ? 0.5 : 1.0, cj = (j == 0 || j == nv) ? 0.5 : 1.0;
      g.uv.push_back(uv);
      g.points.push_back(S);
      g.weight.push_back(Su.cross(Sv).norm() * du * dv * ci * cj);
    }
  if (!mesh) return g;
  auto id = [nv](int i, int j) { return Index(i * (nv + 1) + j); };
  auto add = [&](Index a, Index b, Index c) {
    g.triangles.push_back({a, b, c});
    const Vec2 q = (g.uv[a] + g.uv[b] + g.uv[c]) / 3;
    const Vec3 flat = (g.points[a] + g.points[b] + g.points[c]) / 3;
    g.max_chord = std::max(g.max_chord, (patch.value(q.x(), q.y()) - flat).norm());
  };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      add(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      add(id(i, j), id(i + 1, j + 1), id(i, j + 1));
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
