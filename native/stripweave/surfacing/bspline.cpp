#include "stripweave/surfacing/bspline.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

namespace {

// Knot u_k of the clamped uniform cubic knot vector with n spans
// (k = 0..n+6).
inline double knot(int n, int k) { return std::clamp(double(k - kSplineDegree) / n, 0.0, 1.0); }

}  // namespace

int cubic_basis(int n, double t, double N[4], double dN[4], double d2N[4]) {
  constexpr int p = kSplineDegree;
  t = std::clamp(t, 0.0, 1.0);
  // Away from the clamped ends (basis functions j .. j + 3 whose knots
  // u_j .. u_{j+7} are all evenly spaced: 3 <= j <= n - 4) these are the
  // uniform cubic B-spline's four polynomials in the span's local x: the
  // same values as below at a fraction of the cost (the fit and the
  // deviation evaluate them millions of times).
  const int j = std::min(n - 1, static_cast<int>(std::floor(t * n)));
  if (j >= 3 && j + 4 <= n) {
    const double x = t * n - j, x2 = x * x, x3 = x2 * x, y = 1 - x;
    N[0] = y * y * y / 6;
    N[1] = (3 * x3 - 6 * x2 + 4) / 6;
    N[2] = (-3 * x3 + 3 * x2 + 3 * x + 1) / 6;
    N[3] = x3 / 6;
    if (dN) {
      dN[0] = -0.5 * y * y * n;
      dN[1] = (1.5 * x2 - 2 * x) * n;
      dN[2] = (-1.5 * x2 + x + 0.5) * n;
      dN[3] = 0.5 * x2 * n;
    }
    if (d2N) {
      const double n2 = double(n) * n;
      d2N[0] = y * n2;
      d2N[1] = (3 * x - 2) * n2;
      d2N[2] = (1 - 3 * x) * n2;
      d2N[3] = x * n2;
    }
    return j;
  }
  // Span s with u_{s} <= t < u_{s+1}, s in [p, n + p - 1]; t = 1 belongs to
  // the last span.
  const int span = std::min(n - 1, static_cast<int>(std::floor(t * n))) + p;
  // The NURBS Book A2.3: ndu holds the basis functions of all degrees and
  // the knot differences, from which derivatives follow.
  double ndu[p + 1][p + 1], left[p + 1], right[p + 1];
  ndu[0][0] = 1;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knot(n, span + 1 - j);
    right[j] = knot(n, span + j) - t;
    double saved = 0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= p; ++j) N[j] = ndu[j][p];
  if (dN || d2N) {
    double ders[3][p + 1] = {};
    double a[2][p + 1];
    for (int r = 0; r <= p; ++r) {
      int s1 = 0, s2 = 1;
      a[0][0] = 1;
      for (int k = 1; k <= 2; ++k) {
        double d = 0;
        const int rk = r - k, pk = p - k;
        if (r >= k) {
          a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
          d = a[s2][0] * ndu[rk][pk];
        }
        const int j1 = rk >= -1 ? 1 : -rk;
        const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
        for (int j = j1; j <= j2; ++j) {
          a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
          d += a[s2][j] * ndu[rk + j][pk];
        }
        if (r <= pk) {
          a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
          d += a[s2][k] * ndu[r][pk];
        }
        ders[k][r] = d;
        std::swap(s1, s2);
      }
    }
    for (int j = 0; j <= p; ++j) {
      if (dN) dN[j] = ders[1][j] * p;
      if (d2N) d2N[j] = ders[2][j] * p * (p - 1);
    }
  }
  return span - p;
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

void BSplinePatch::evaluate(double u, double v, Vec3* S, Vec3* Su, Vec3* Sv) const {
  double Nu[4], dNu[4], Nv[4], dNv[4];
  const int iu = cubic_basis(nu, u, Nu, dNu);
  const int iv = cubic_basis(nv, v, Nv, dNv);
  Vec3 s = Vec3::Zero(), su = Vec3::Zero(), sv = Vec3::Zero();
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      const Vec3& c = P(iu + a, iv + b);
      s += Nu[a] * Nv[b] * c;
      su += dNu[a] * Nv[b] * c;
      sv += Nu[a] * dNv[b] * c;
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
