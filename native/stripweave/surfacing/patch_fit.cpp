#include "stripweave/surfacing/patch_fit.h"

#include "stripweave/core/error.h"
#include "stripweave/core/parallel.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>

namespace stripweave {

namespace {

// Normal equations of one patch over its whole control grid, in band form:
// control (i, j) couples to (i + di, j + dj) with |di|, |dj| <= 3 (the
// support of bicubic basis products).
struct BandSystem {
  int rows = 0, cols = 0;
  std::vector<double> band;  // rows*cols*49
  Eigen::MatrixXd rhs;       // rows*cols x 3

  BandSystem(int r, int c) : rows(r), cols(c), band(size_t(r) * c * 49, 0.0), rhs(Eigen::MatrixXd::Zero(r * c, 3)) {}
  double& at(int i, int j, int di, int dj) { return band[(size_t(i) * cols + j) * 49 + (di + 3) * 7 + (dj + 3)]; }
  double at(int i, int j, int di, int dj) const { return band[(size_t(i) * cols + j) * 49 + (di + 3) * 7 + (dj + 3)]; }

  // Add w * (sum_a coef_a P_a)^2 (a homogeneous difference stencil).
  void add_stencil(const std::array<int, 2>* idx, const double* coef, int n, double w) {
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        at(idx[a][0], idx[a][1], idx[b][0] - idx[a][0], idx[b][1] - idx[a][1]) += w * coef[a] * coef[b];
  }
};

bool is_free(const BSplinePatch& p, int i, int j) { return i >= 1 && j >= 1 && i <= p.rows() - 2 && j <= p.cols() - 2; }

BandSystem assemble(const BSplinePatch& p, const PatchSamples& s, double smoothing, double* mean_diag) {
  BandSystem sys(p.rows(), p.cols());
  const double w = s.points.empty() ? 0.0 : 1.0 / s.points.size();
  for (size_t k = 0; k < s.points.size(); ++k) {
    double Nu[4], Nv[4];
    const int iu = cubic_basis(p.nu, s.uv[k].x(), Nu);
    const int iv = cubic_basis(p.nv, s.uv[k].y(), Nv);
    double B[16];
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) B[a * 4 + b] = Nu[a] * Nv[b];
    for (int x = 0; x < 16; ++x) {
      const int i = iu + x / 4, j = iv + x % 4;
      sys.rhs.row(i * sys.cols + j) += w * B[x] * s.points[k].transpose();
      for (int y = 0; y < 16; ++y) sys.at(i, j, y / 4 - x / 4, y % 4 - x % 4) += w * B[x] * B[y];
    }
  }
  // Mean data diagonal over the free controls: the scale of the seam weight.
  double sum = 0;
  int count = 0;
  for (int i = 1; i <= p.rows() - 2; ++i)
    for (int j = 1; j <= p.cols() - 2; ++j) sum += sys.at(i, j, 0, 0), ++count;
  *mean_diag = count ? sum / count : 0.0;

  // Thin-plate energy in control-point differences.
  const double nu = p.nu, nv = p.nv, area = 1.0 / (nu * nv);
  const double wuu = smoothing * std::pow(nu, 4) * area, wvv = smoothing * std::pow(nv, 4) * area;
  const double wuv = 2 * smoothing * nu * nu * nv * nv * area;
  const double c3[3] = {1, -2, 1}, c4[4] = {1, -1, -1, 1};
  for (int i = 0; i < p.rows(); ++i)
    for (int j = 0; j < p.cols(); ++j) {
      if (i + 2 < p.rows()) {
        const std::array<int, 2> idx[3] = {{i, j}, {i + 1, j}, {i + 2, j}};
        sys.add_stencil(idx, c3, 3, wuu);
      }
      if (j + 2 < p.cols()) {
        const std::array<int, 2> idx[3] = {{i, j}, {i, j + 1}, {i, j + 2}};
        sys.add_stencil(idx, c3, 3, wvv);
      }
      if (i + 1 < p.rows() && j + 1 < p.cols()) {
        const std::array<int, 2> idx[4] = {{i, j}, {i + 1, j}, {i, j + 1}, {i + 1, j + 1}};
        sys.add_stencil(idx, c4, 4, wuv);
      }
    }
  if (*mean_diag <= 0) {
    sum = 0;
    for (int i = 1; i <= p.rows() - 2; ++i)
      for (int j = 1; j <= p.cols() - 2; ++j) sum += sys.at(i, j, 0, 0);
    *mean_diag = count ? sum / count : 1.0;
  }
  return sys;
}

// One least-squares system for the patches `which` (seams between two of
// them coupled); writes only their inner controls.
void solve_interiors(std::vector<BSplinePatch>& patches, const std::vector<PatchSamples>& samples,
                     const std::vector<Index>& which, const std::vector<Seam>& seams, double smoothing,
                     double seam_weight, const std::vector<ControlTarget>& targets, double target_weight) {
  // Global numbering of the free controls of the solved patches.
  std::vector<Index> offset(patches.size(), kInvalid);
  Index n = 0;
  for (Index p : which) {
    offset[p] = n;
    n += (patches[p].rows() - 2) * (patches[p].cols() - 2);
  }
  if (n == 0) return;
  auto gid = [&](Index p, int i, int j) { return offset[p] + (i - 1) * (patches[p].cols() - 2) + (j - 1); };

  std::vector<Eigen::Triplet<double>> trip;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
  std::vector<double> mean_diag(patches.size(), 0.0);
  for (Index p : which) {
    const BSplinePatch& P = patches[p];
    const BandSystem sys = assemble(P, samples[p], smoothing, &mean_diag[p]);
    for (int i = 1; i <= P.rows() - 2; ++i)
      for (int j = 1; j <= P.cols() - 2; ++j) {
        const Index r = gid(p, i, j);
        rhs.row(r) += sys.rhs.row(i * P.cols() + j);
        for (int di = -3; di <= 3; ++di)
          for (int dj = -3; dj <= 3; ++dj) {
            const int i2 = i + di, j2 = j + dj;
            if (i2 < 0 || j2 < 0 || i2 >= P.rows() || j2 >= P.cols()) continue;
            const double a = sys.at(i, j, di, dj);
            if (a == 0) continue;
            if (!is_free(P, i2, j2)) {
              rhs.row(r) -= a * P.P(i2, j2).transpose();  // boundary rows are known
              continue;
            }
            const Index c = gid(p, i2, j2);
            if (c <= r) trip.emplace_back(r, c, a);  // the lower triangle (see below)
          }
      }
  }

  // C1 penalties across smooth seams between solved patches.
  if (seam_weight > 0)
    for (const Seam& s : seams) {
      if (offset[s.a] == kInvalid || offset[s.b] == kInvalid) continue;
      const BSplinePatch &A = patches[s.a], &B = patches[s.b];
      const int N = side_size(A, s.side_a);
      if (side_size(B, s.side_b) != N) continue;  // no common knot vector: cannot couple
      const double w = seam_weight * 0.5 * (mean_diag[s.a] + mean_diag[s.b]) / (1 + s.alpha * s.alpha);
      for (int m = 1; m <= N - 2; ++m) {
        const auto ca = side_control(A, s.side_a, m, 1);
        const auto cb = side_control(B, s.side_b, s.b_reversed ? N - 1 - m : m, 1);
        const auto q = side_control(A, s.side_a, m, 0);
        const Index ga = gid(s.a, ca[0], ca[1]), gb = gid(s.b, cb[0], cb[1]);
        const double coef[2] = {1, s.alpha};
        const Index g[2] = {ga, gb};
        const Eigen::RowVector3d target = (1 + s.alpha) * A.P(q[0], q[1]).transpose();
        for (int x = 0; x < 2; ++x) {
          rhs.row(g[x]) += w * coef[x] * target;
          for (int y = 0; y < 2; ++y)
            if (g[y] <= g[x]) trip.emplace_back(g[x], g[y], w * coef[x] * coef[y]);
        }
      }
    }

  if (target_weight > 0)
    for (const ControlTarget& t : targets) {
      if (t.patch < 0 || offset[t.patch] == kInvalid || !is_free(patches[t.patch], t.i, t.j)) continue;
      const Index g = gid(t.patch, t.i, t.j);
      const double w = target_weight * mean_diag[t.patch];
      rhs.row(g) += w * t.target.transpose();
      trip.emplace_back(g, g, w);
    }

  // Only the lower triangle is assembled (the factorization reads no more),
  // and the triplets go before the factor is made: on a network of 86 finely
  // refined patches (142,500 unknowns, 14M nonzeros in L) the full matrix
  // and its triplets beside the factor were a third of the refit's peak.
  Eigen::SparseMatrix<double> M(n, n);
  M.setFromTriplets(trip.begin(), trip.end());
  std::vector<Eigen::Triplet<double>>().swap(trip);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver(M);
  if (solver.info() != Eigen::Success) throw InputError("patch surface fit failed: singular least-squares system");
  const Eigen::MatrixXd x = solver.solve(rhs);
  for (Index p : which) {
    BSplinePatch& P = patches[p];
    for (int i = 1; i <= P.rows() - 2; ++i)
      for (int j = 1; j <= P.cols() - 2; ++j) P.P(i, j) = x.row(gid(p, i, j)).transpose();
  }
}

}  // namespace

void fit_patch_interiors(std::vector<BSplinePatch>& patches, const std::vector<PatchSamples>& samples,
                         const std::vector<Index>& which_in, const std::vector<Seam>& seams, double smoothing,
                         double seam_weight, const std::vector<ControlTarget>& targets, double target_weight) {
  std::vector<Index> which = which_in;
  if (which.empty())
    for (Index p = 0; p < static_cast<Index>(patches.size()); ++p) which.push_back(p);
  // Patches no seam couples are independent systems: one per group of
  // coupled patches (each in the order of `which`), solved side by side.
  // An uncoupled refinement round is a group per patch; the coupled fit of
  // a connected network, one group.
  std::vector<Index> root(patches.size(), kInvalid);
  for (Index p : which) root[p] = p;
  auto find = [&](Index p) {
    while (root[p] != p) p = root[p] = root[root[p]];
    return p;
  };
  if (seam_weight > 0)
    for (const Seam& sm : seams)
      if (root[sm.a] != kInvalid && root[sm.b] != kInvalid) {
        const Index a = find(sm.a), b = find(sm.b);
        if (a != b) root[std::max(a, b)] = std::min(a, b);
      }
  std::vector<std::vector<Index>> groups;
  std::vector<Index> group_of(patches.size(), kInvalid);
  for (Index p : which) {
    const Index r = find(p);
    if (group_of[r] == kInvalid) group_of[r] = static_cast<Index>(groups.size()), groups.emplace_back();
    groups[group_of[r]].push_back(p);
  }
  parallel_for(static_cast<Index>(groups.size()), [&](Index g) {
    solve_interiors(patches, samples, groups[g], seams, smoothing, seam_weight, targets, target_weight);
  });
}

double seam_speed_ratio(const std::vector<BSplinePatch>& patches, const Seam& s) {
  const BSplinePatch &A = patches[s.a], &B = patches[s.b];
  const int N = side_size(A, s.side_a);
  if (side_size(B, s.side_b) != N) return 1.0;
  double la = 0, lb = 0;
  for (int m = 1; m <= N - 2; ++m) {
    const auto q = side_control(A, s.side_a, m, 0);
    const auto ca = side_control(A, s.side_a, m, 1);
    const auto cb = side_control(B, s.side_b, s.b_reversed ? N - 1 - m : m, 1);
    la += (A.P(ca[0], ca[1]) - A.P(q[0], q[1])).norm();
    lb += (B.P(cb[0], cb[1]) - A.P(q[0], q[1])).norm();
  }
  return (la > 0 && lb > 0) ? la / lb : 1.0;
}

double distance_to_patch(const BSplinePatch& patch, const Vec3& p, Vec2 uv, Vec2* foot) {
  // Gauss-Newton, each step halved until it brings the point closer: on a
  // strongly curved patch (a thread, a fillet), or from a harmonic (u, v)
  // some way off the foot point, a full step can overshoot and the plain
  // iteration settle nowhere, overstating the deviation.
  // Each trial point is evaluated with its derivatives, so an accepted one
  // starts the next step without being evaluated again (the same sums as
  // value(): the same figures, half the evaluations).
  Vec3 S, Su, Sv;
  patch.evaluate(uv.x(), uv.y(), &S, &Su, &Sv);
  double best = (S - p).squaredNorm();
  for (int it = 0; it < 12; ++it) {
    const Vec3 r = p - S;
    Eigen::Matrix2d J;
    J << Su.dot(Su), Su.dot(Sv), Su.dot(Sv), Sv.dot(Sv);
    const Vec2 g(Su.dot(r), Sv.dot(r));
    if (std::abs(J.determinant()) < 1e-300) break;
    Vec2 step = J.ldlt().solve(g);
    bool better = false;
    for (int half = 0; half < 6 && !better; ++half, step *= 0.5) {
      const Vec2 next = (uv + step).cwiseMax(0.0).cwiseMin(1.0);
      Vec3 T, Tu, Tv;
      patch.evaluate(next.x(), next.y(), &T, &Tu, &Tv);
      const double d = (T - p).squaredNorm();
      if (d < best) best = d, uv = next, better = true, S = T, Su = Tu, Sv = Tv;
    }
    if (!better || step.squaredNorm() < 1e-24) break;
  }
  if (foot) *foot = uv;
  return std::sqrt(best);
}

}  // namespace stripweave
