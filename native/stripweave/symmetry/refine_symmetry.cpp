#include "stripweave/symmetry/refine_symmetry.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace stripweave {

namespace {

Symmetry refit_reflection(const Symmetry& s, const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 d = p[i] - q[i];
    scatter += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  Vec3 n = eigen.eigenvectors().col(2);
  if (!n.allFinite() || eigen.eigenvalues()(2) <= 0) return s;
  if (n.dot(s.direction) < 0) n = -n;
  double offset = 0;
  for (std::size_t i = 0; i < p.size(); ++i) offset += n.dot(0.5 * (p[i] + q[i]));
  offset /= static_cast<double>(p.size());
  // Keep the plane's point near the old one (the point is free within the plane).
  const Vec3 point = s.point + (offset - n.dot(s.point)) * n;
  return Symmetry::reflection(point, n);
}

Symmetry refit_rotation(const Symmetry& s, const std::vector<Vec3>& p, const std::vector<Vec3>& q) {
  Vec3 cp = Vec3::Zero(), cq = Vec3::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) {
    cp += p[i];
    cq += q[i];
  }
  cp /= static_cast<double>(p.size());
  cq /= static_cast<double>(p.size());
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) h += (p[i] - cp) * (q[i] - cq).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) d(2, 2) = -1;
  const Eigen::Matrix3d r = svd.matrixV() * d * svd.matrixU().transpose();
  const Vec3 t = cq - r * cp;
  Vec3 axis(r(2, 1) - r(1, 2), r(0, 2) - r(2, 0), r(1, 0) - r(0, 1));
  if (!(axis.norm() > 1e-12)) return s;
  axis.normalize();
  if (axis.dot(s.direction) < 0) axis = -axis;
  // (I - R) x = t has a line of solutions along the axis: the minimum-norm one
  // relative to the old point, then moved onto the old point's plane.
  const Eigen::Matrix3d a = Eigen::Matrix3d::Identity() - r;
  const Vec3 rhs = t - a * s.point;
  const Vec3 x = s.point + a.completeOrthogonalDecomposition().solve(rhs);
  if (!x.allFinite()) return s;
  const Vec3 point = x - axis * axis.dot(x - s.point);
  return Symmetry::rotation(point, axis, s.order);
}

}  // namespace

Symmetry refine_symmetry(const Symmetry& candidate, const std::vector<Vec3>& samples, const SurfaceLocator& locator,
                         int iterations) {
  Symmetry s = candidate;
  if (samples.size() < 3) return s;
  Symmetry best = s;
  double best_rms = std::numeric_limits<double>::infinity();
  for (int it = 0; it < iterations; ++it) {
    const SymmetryError e = symmetry_error(s, samples, locator, std::numeric_limits<double>::infinity(), true);
    // ICP only ever approaches a nearby symmetry: a step that does not lower
    // the error by 1% means there is none here (or it is reached).
    if (!(e.rms < 0.99 * best_rms)) break;
    best = s;
    best_rms = e.rms;
    // Pair each sample with the closest surface point to its image: fitting
    // p -> q gives the map itself.
    const Symmetry next = s.kind == SymmetryKind::Reflection ? refit_reflection(s, samples, e.closest)
                                                             : refit_rotation(s, samples, e.closest);
    const double moved = (next.point - s.point).norm() + (next.direction - s.direction).norm();
    s = next;
    if (moved < 1e-10) return s;
  }
  return best;
}

}  // namespace stripweave
