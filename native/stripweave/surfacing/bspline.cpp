#include "stripweave/surfacing/bspline.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

namespace {

// The cubic basis on one span of a clamped uniform knot vector, as
// polynomials in the span's local x in [0, 1]. The four functions nonzero on
// span j depend only on the knots u_{j+1} .. u_{j+6} (The NURBS Book, §2.2),
// which in units of the span, relative to u_{j+3} = 0, are -2 .. 3 clamped to
// [-L, R + 1] with L = min(j, 2) spans to the left end and R = min(n-1-j, 2)
// to the right. So there are nine span shapes; kSpanShape[L][R][a][k] is the
// coefficient of x^k of the a-th function, derived by Cox-de Boor in exact
// rational arithmetic (the spans of a spline with n >= 5 spans away from its
// ends are the uniform B-spline's, L = R = 2). The fit and the deviation
// evaluate these millions of times, and most patches have few spans: the
// table replaces the general recursion at the ends.
constexpr double kSpanShape[3][3][4][4] = {
    {{{1.0, -3.0, 3.0, -1.0}, {0.0, 3.0, -6.0, 3.0}, {0.0, 0.0, 3.0, -3.0}, {0.0, 0.0, 0.0, 1.0}},
     {{1.0, -3.0, 3.0, -1.0}, {0.0, 3.0, -9.0 / 2, 7.0 / 4}, {0.0, 0.0, 3.0 / 2, -1.0}, {0.0, 0.0, 0.0, 1.0 / 4}},
     {{1.0, -3.0, 3.0, -1.0}, {0.0, 3.0, -9.0 / 2, 7.0 / 4}, {0.0, 0.0, 3.0 / 2, -11.0 / 12}, {0.0, 0.0, 0.0, 1.0 / 6}}},
    {{{1.0 / 4, -3.0 / 4, 3.0 / 4, -1.0 / 4}, {1.0 / 2, 0.0, -3.0 / 2, 1.0}, {1.0 / 4, 3.0 / 4, 3.0 / 4, -7.0 / 4},
      {0.0, 0.0, 0.0, 1.0}},
     {{1.0 / 4, -3.0 / 4, 3.0 / 4, -1.0 / 4}, {7.0 / 12, 1.0 / 4, -5.0 / 4, 7.0 / 12},
      {1.0 / 6, 1.0 / 2, 1.0 / 2, -7.0 / 12}, {0.0, 0.0, 0.0, 1.0 / 4}},
     {{1.0 / 4, -3.0 / 4, 3.0 / 4, -1.0 / 4}, {7.0 / 12, 1.0 / 4, -5.0 / 4, 7.0 / 12},
      {1.0 / 6, 1.0 / 2, 1.0 / 2, -1.0 / 2}, {0.0, 0.0, 0.0, 1.0 / 6}}},
    {{{1.0 / 6, -1.0 / 2, 1.0 / 2, -1.0 / 6}, {7.0 / 12, -1.0 / 4, -5.0 / 4, 11.0 / 12},
      {1.0 / 4, 3.0 / 4, 3.0 / 4, -7.0 / 4}, {0.0, 0.0, 0.0, 1.0}},
     {{1.0 / 6, -1.0 / 2, 1.0 / 2, -1.0 / 6}, {2.0 / 3, 0.0, -1.0, 1.0 / 2}, {1.0 / 6, 1.0 / 2, 1.0 / 2, -7.0 / 12},
      {0.0, 0.0, 0.0, 1.0 / 4}},
     {{1.0 / 6, -1.0 / 2, 1.0 / 2, -1.0 / 6}, {2.0 / 3, 0.0, -1.0, 1.0 / 2}, {1.0 / 6, 1.0 / 2, 1.0 / 2, -1.0 / 2},
      {0.0, 0.0, 0.0, 1.0 / 6}}}};

}  // namespace

int cubic_basis(int n, double t, double N[4], double dN[4], double d2N[4]) {
  n = std::max(n, 1);
  t = std::clamp(t, 0.0, 1.0);
  // Span j with u_j <= t < u_{j+1} (in span units); t = 1 belongs to the last span.
  const int j = std::min(n - 1, static_cast<int>(std::floor(t * n)));
  const double x = t * n - j;
  const auto& shape = kSpanShape[std::min(j, 2)][std::min(n - 1 - j, 2)];
  for (int a = 0; a < 4; ++a) {
    const double* c = shape[a];
    N[a] = c[0] + x * (c[1] + x * (c[2] + x * c[3]));
    // d/dt = n d/dx.
    if (dN) dN[a] = n * (c[1] + x * (2 * c[2] + x * 3 * c[3]));
    if (d2N) d2N[a] = double(n) * n * (2 * c[2] + 6 * c[3] * x);
  }
  return j;
}

Vec3 BSplineCurve3::value(double t) const {
  double N[4];
  const int first = cubic_basis(spans, t, N);
  Vec3 s = Vec3::Zero();
  for (int a = 0; a < 4; ++a) s += N[a] * control[first + a];
  return s;
}

Vec3 BSplineCurve3::derivative(double t) const {
  double N[4], dN[4];
  const int first = cubic_basis(spans, t, N, dN);
  Vec3 s = Vec3::Zero();
  for (int a = 0; a < 4; ++a) s += dN[a] * control[first + a];
  return s;
}

CubicBasis cubic_basis_at(int n, double t) {
  CubicBasis b;
  b.first = cubic_basis(n, t, b.N, b.dN);
  return b;
}

void BSplinePatch::evaluate(double u, double v, Vec3* S, Vec3* Su, Vec3* Sv) const {
  evaluate(cubic_basis_at(nu, u), cubic_basis_at(nv, v), S, Su, Sv);
}

void BSplinePatch::evaluate(const CubicBasis& bu, const CubicBasis& bv, Vec3* S, Vec3* Su, Vec3* Sv) const {
  // Each sum is accumulated on its own, so leaving out the partials (value())
  // changes no bit of the position.
  Vec3 s = Vec3::Zero(), su = Vec3::Zero(), sv = Vec3::Zero();
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      const Vec3& c = P(bu.first + a, bv.first + b);
      if (S) s += bu.N[a] * bv.N[b] * c;
      if (Su) su += bu.dN[a] * bv.N[b] * c;
      if (Sv) sv += bu.N[a] * bv.dN[b] * c;
    }
  if (S) *S = s;
  if (Su) *Su = su;
  if (Sv) *Sv = sv;
}

Vec3 BSplinePatch::value(double u, double v) const {
  Vec3 s;
  evaluate(u, v, &s, nullptr, nullptr);
  return s;
}

Vec3 BSplinePatch::normal(double u, double v) const {
  Vec3 su, sv;
  evaluate(u, v, nullptr, &su, &sv);
  const Vec3 n = su.cross(sv);
  const double len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

int side_size(const BSplinePatch& p, int side) { return side % 2 == 0 ? p.rows() : p.cols(); }

std::array<int, 2> side_control(const BSplinePatch& p, int side, int k, int depth) {
  const int I = p.rows() - 1, J = p.cols() - 1;
  switch (side) {
    case 0: return {k, depth};
    case 1: return {I - depth, k};
    case 2: return {I - k, J - depth};
    default: return {depth, J - k};
  }
}

Vec2 side_uv(int side, double t) {
  switch (side) {
    case 0: return {t, 0};
    case 1: return {1, t};
    case 2: return {1 - t, 1};
    default: return {0, 1 - t};
  }
}

}  // namespace stripweave
