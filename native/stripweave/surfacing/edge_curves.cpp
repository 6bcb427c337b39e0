#include "stripweave/surfacing/edge_curves.h"

#include "stripweave/core/error.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace stripweave {

EdgeSamples sample_edge(const std::vector<Vec3>& polyline, const std::vector<std::vector<Index>>& point_faces,
                        bool sharp, const SourceProjector& projector, int density, double smooth) {
  EdgeSamples out;
  const size_t n = polyline.size();
  if (n < 2) throw InputError("a network edge polyline has fewer than 2 points");
  auto project = [&](const Vec3& p, const std::vector<Index>& faces) {
    return sharp ? projector.on_sharp(faces, p) : projector.on_faces(faces, p);
  };
  std::vector<std::vector<Index>> sample_faces;  // per sample, the faces it may lie on
  // The ends are the network vertices themselves, kept exactly.
  out.points.push_back(polyline.front());
  sample_faces.push_back(point_faces.empty() ? std::vector<Index>{} : point_faces.front());
  for (size_t k = 0; k + 1 < n; ++k) {
    // A point inside segment k may lie on any face of either end point.
    std::vector<Index> faces;
    if (!point_faces.empty()) {
      faces = point_faces[k];
      faces.insert(faces.end(), point_faces[k + 1].begin(), point_faces[k + 1].end());
      std::sort(faces.begin(), faces.end());
      faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    }
    for (int s = 1; s <= density; ++s) {
      const double a = double(s) / density;
      if (k + 2 == n && s == density) break;  // the end vertex, added below
      const Vec3 p = (1 - a) * polyline[k] + a * polyline[k + 1];
      sample_faces.push_back(s == density && !point_faces.empty() ? point_faces[k + 1] : faces);
      out.points.push_back(project(p, sample_faces.back()));
    }
  }
  out.points.push_back(polyline.back());
  sample_faces.push_back(point_faces.empty() ? std::vector<Index>{} : point_faces.back());
  auto arc_length = [&]() {
    out.t.assign(out.points.size(), 0.0);
    for (size_t k = 1; k < out.points.size(); ++k)
      out.t[k] = out.t[k - 1] + (out.points[k] - out.points[k - 1]).norm();
  };
  arc_length();
  const double L = out.t.back();
  if (L <= 0) throw InputError("a network edge has zero length");
  const size_t m = out.points.size();
  if (smooth > 0 && !sharp && m > 2) {
    const double sigma = smooth * L / double(n - 1);
    const Vec3 a = out.points.front(), b = out.points.back();
    std::vector<Vec3> filtered(out.points);
    for (size_t i = 1; i + 1 < m; ++i) {
      const double si = out.t[i];
      Vec3 sum = Vec3::Zero();
      double wsum = 0;
      auto add = [&](double s, const Vec3& p) {
        const double d = (s - si) / sigma;
        if (std::abs(d) > 3) return;
        const double w = std::exp(-0.5 * d * d);
        sum += w * p, wsum += w;
      };
      for (size_t j = 0; j < m; ++j) {
        add(out.t[j], out.points[j]);
        if (j > 0 && out.t[j] < 3 * sigma) add(-out.t[j], 2 * a - out.points[j]);  // reflected about the start
        if (j + 1 < m && L - out.t[j] < 3 * sigma) add(2 * L - out.t[j], 2 * b - out.points[j]);  // about the end
      }
      filtered[i] = project(sum / wsum, sample_faces[i]);
    }
    out.points = std::move(filtered);
    arc_length();
  }
  for (double& x : out.t) x /= out.t.back();
  return out;
}

// Largest angle (degrees) between a free end tangent and the vertex's
// tangent plane for which the end is held in the plane.
constexpr double kMaxTangentTilt = 5.0;
constexpr int kMaxEdgeCurveSpans = 1 << 20;

BSplineCurve3 fit_edge_curve(const EdgeSamples& samples, const Vec3& start, const Vec3& end, int spans,
                             double smoothing, const Vec3& start_normal, const Vec3& end_normal) {
  // Every caller asks for 1 span or more (the fit's span counts); the bound
  // keeps the control count N = spans + 3 and its indices from overflowing.
  if (spans < 1 || spans > kMaxEdgeCurveSpans) throw std::invalid_argument("fit_edge_curve: span count out of range");
  BSplineCurve3 c;
  c.spans = spans;
  const int N = spans + 3;
  c.control.assign(N, Vec3::Zero());
  c.control.front() = start;
  c.control.back() = end;
  // Unknowns: controls 1..N-2 (index shifted by one).
  const int M = N - 2;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(M, M);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(M, 3);
  const double wdata = 1.0 / samples.points.size();
  for (size_t k = 0; k < samples.points.size(); ++k) {
    double Nb[4];
    const int first = cubic_basis(spans, samples.t[k], Nb);
    Eigen::RowVector3d r = samples.points[k].transpose();
    for (int a = 0; a < 4; ++a) {
      const int ia = first + a;
      if (ia == 0) r -= Nb[a] * start.transpose();
      if (ia == N - 1) r -= Nb[a] * end.transpose();
    }
    for (int a = 0; a < 4; ++a) {
      const int ia = first + a - 1;
      if (ia < 0 || ia >= M) continue;
      b.row(ia) += wdata * Nb[a] * r;
      for (int c2 = 0; c2 < 4; ++c2) {
        const int ib = first + c2 - 1;
        if (ib >= 0 && ib < M) A(ia, ib) += wdata * Nb[a] * Nb[c2];
      }
    }
  }
  // Bending: second differences of consecutive controls.
  const double wbend = smoothing * std::pow(double(spans), 3);
  for (int i = 1; i + 1 < N; ++i) {
    const int idx[3] = {i - 1, i, i + 1};
    const double coef[3] = {1, -2, 1};
    Eigen::RowVector3d fixed = Eigen::RowVector3d::Zero();
    for (int a = 0; a < 3; ++a) {
      if (idx[a] == 0) fixed += coef[a] * start.transpose();
      if (idx[a] == N - 1) fixed += coef[a] * end.transpose();
    }
    for (int a = 0; a < 3; ++a) {
      const int ia = idx[a] - 1;
      if (ia < 0 || ia >= M) continue;
      b.row(ia) -= wbend * coef[a] * fixed;
      for (int c2 = 0; c2 < 3; ++c2) {
        const int ib = idx[c2] - 1;
        if (ib >= 0 && ib < M) A(ia, ib) += wbend * coef[a] * coef[c2];
      }
    }
  }
  // A tiny ridge keeps controls without samples at the chord (never active
  // on densely sampled edges).
  const double ridge = 1e-12 * std::max(A.diagonal().maxCoeff(), 1e-300);
  for (int i = 0; i < M; ++i) {
    A(i, i) += ridge;
    const double s = double(i + 1) / (N - 1);
    b.row(i) += ridge * ((1 - s) * start + s * end).transpose();
  }
  {
    const Eigen::MatrixXd x = A.ldlt().solve(b);
    for (int i = 0; i < M; ++i) c.control[i + 1] = x.row(i).transpose();
  }
  // Only an end whose free tangent already lies near the plane is held in
  // it: one far out of it (a vertex by a crease, a curve too coarse to
  // bend in time) would be forced into a hook that folds the patches.
  auto near_plane = [&](const Vec3& normal, const Vec3& tangent) {
    if (normal.isZero() || tangent.isZero()) return false;
    return std::abs(normal.normalized().dot(tangent.normalized())) < std::sin(kMaxTangentTilt * M_PI / 180.0);
  };
  const Vec3 start_n = near_plane(start_normal, c.control[1] - start) ? start_normal : Vec3::Zero();
  const Vec3 end_n = near_plane(end_normal, c.control[N - 2] - end) ? end_normal : Vec3::Zero();
  if (start_n.isZero() && end_n.isZero()) return c;
  // End tangents in the vertices' tangent planes: the penalty
  // w ((P_1 - start) . n)^2 couples x, y and z, so the three share one
  // 3M x 3M system (M <= max_spans + 1: small and dense); the rest of the
  // curve still follows the samples. The ends are then put exactly in
  // their planes.
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * M, 3 * M);
  Eigen::VectorXd r(3 * M);
  for (int i = 0; i < M; ++i) {
    for (int j = 0; j < M; ++j) K.block<3, 3>(3 * i, 3 * j) = A(i, j) * Eigen::Matrix3d::Identity();
    r.segment<3>(3 * i) = b.row(i).transpose();
  }
  const double w = 1e6 * A.diagonal().maxCoeff();
  auto plane = [&](int i, const Vec3& normal, const Vec3& at) {
    if (normal.isZero()) return;
    const Vec3 n = normal.normalized();
    K.block<3, 3>(3 * i, 3 * i) += w * n * n.transpose();
    r.segment<3>(3 * i) += w * n * n.dot(at);
  };
  plane(0, start_n, start);
  plane(M - 1, end_n, end);
  const Eigen::VectorXd x = K.ldlt().solve(r);
  for (int i = 0; i < M; ++i) c.control[i + 1] = x.segment<3>(3 * i);
  if (!start_n.isZero()) {
    const Vec3 n = start_n.normalized();
    c.control[1] -= (c.control[1] - start).dot(n) * n;
  }
  if (!end_n.isZero()) {
    const Vec3 n = end_n.normalized();
    c.control[N - 2] -= (c.control[N - 2] - end).dot(n) * n;
  }
  return c;
}

double edge_curve_deviation(const BSplineCurve3& curve, const EdgeSamples& samples) {
  double worst = 0;
  for (size_t k = 0; k < samples.points.size(); ++k) {
    double t = samples.t[k];
    const Vec3& p = samples.points[k];
    for (int it = 0; it < 4; ++it) {
      const Vec3 d = curve.derivative(t);
      const double dd = d.squaredNorm();
      if (dd <= 0) break;
      t = std::clamp(t + (p - curve.value(t)).dot(d) / dd, 0.0, 1.0);
    }
    worst = std::max(worst, (curve.value(t) - p).norm());
  }
  return worst;
}

}  // namespace stripweave
