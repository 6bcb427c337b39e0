// Uniform clamped cubic B-splines: the one spline space the surfacing stage
// uses for edge curves and patch surfaces (no OCCT type here).
//
//   A spline with n spans has degree 3, the clamped uniform knot vector
//     0,0,0,0, 1/n, 2/n, ..., (n-1)/n, 1,1,1,1
//   and n + 3 control points. Clamping makes the curve interpolate its first
//   and last control points; uniformity makes the knot vector symmetric, so a
//   curve run backwards is the same spline with its control points reversed.
//   This is what makes seams watertight by construction: an edge curve with
//   n spans and the side of a patch with n spans in that direction are the
//   same curve when they share their control points (possibly reversed).
//
//   cubic_basis(n, t, N, dN, d2N)  the 4 nonzero basis functions at t in
//       [0, 1] (and their first/second derivatives), returning the index of
//       the first of them: per span a polynomial in the span's local
//       parameter, one of nine span shapes derived by Cox-de Boor (The NURBS
//       Book §2.2; bspline.cpp)
//   BSplineCurve3    n spans, control points; value(t), derivative(t)
//   cubic_basis_at(n, t)  the same basis and derivatives kept (CubicBasis),
//       to evaluate a patch at many points sharing a u or a v
//   BSplinePatch     nu x nv spans, control grid P(i, j), i along u
//                    (0..nu+2), j along v (0..nv+2); value(u, v) and first
//                    partials, at (u, v) or from a CubicBasis in each
#pragma once

#include "stripweave/core/types.h"

namespace stripweave {

constexpr int kSplineDegree = 3;

// The 4 nonzero cubic basis functions at t (clamped to [0, 1]) on n uniform
// spans; returns the index of the first. dN / d2N may be null.
int cubic_basis(int n, double t, double N[4], double dN[4] = nullptr, double d2N[4] = nullptr);

// The basis at one parameter, kept to be reused: a grid's nodes share their
// u along a row and their v along a column, so the basis is evaluated once
// per row and column instead of at every node (BSplinePatch::evaluate).
struct CubicBasis {
  int first = 0;
  double N[4] = {0, 0, 0, 0}, dN[4] = {0, 0, 0, 0};
};
CubicBasis cubic_basis_at(int n, double t);

struct BSplineCurve3 {
  int spans = 1;
  std::vector<Vec3> control;  // spans + 3

  Vec3 value(double t) const;
  Vec3 derivative(double t) const;
};

struct BSplinePatch {
  int nu = 1, nv = 1;          // spans in u and v
  std::vector<Vec3> control;   // (nu + 3) * (nv + 3), index i * (nv + 3) + j

  int rows() const { return nu + 3; }  // along u
  int cols() const { return nv + 3; }  // along v
  Index index(int i, int j) const { return i * cols() + j; }
  Vec3& P(int i, int j) { return control[index(i, j)]; }
  const Vec3& P(int i, int j) const { return control[index(i, j)]; }

  Vec3 value(double u, double v) const;
  // Position and first partials at (u, v); the partials are summed only
  // when asked for.
  void evaluate(double u, double v, Vec3* S, Vec3* Su, Vec3* Sv) const;
  // The same sums (to the bit) from the basis at u (on nu spans) and at v
  // (on nv spans), evaluated beforehand.
  void evaluate(const CubicBasis& bu, const CubicBasis& bv, Vec3* S, Vec3* Su, Vec3* Sv) const;
  // Unit normal Su x Sv (outward for a patch whose sides run counter-
  // clockwise seen from outside), zero where degenerate.
  Vec3 normal(double u, double v) const;
};

// Grid index (i, j) of the control point k along side s (0..3, counter-
// clockwise: v = 0, u = 1, v = 1, u = 0, each run in its ccw direction),
// `depth` rows inward. Side s has nu + 3 (s even) or nv + 3 (s odd) points.
std::array<int, 2> side_control(const BSplinePatch& p, int side, int k, int depth);
int side_size(const BSplinePatch& p, int side);
// The point of side s at its ccw parameter t in [0, 1], as (u, v).
Vec2 side_uv(int side, double t);

}  // namespace stripweave
