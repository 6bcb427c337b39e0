#include "stripweave/symmetry/symmetry.h"

#include "stripweave/core/error.h"

#include <cmath>
#include <string>

namespace stripweave {

namespace {

Vec3 unit(const Vec3& v, const char* what) {
  const double n = v.norm();
  if (!std::isfinite(n) || n <= 1e-300) throw InputError(std::string("a symmetry's ") + what + " must be a non-zero, finite vector");
  return v / n;
}

void check_point(const Vec3& p) {
  if (!p.allFinite()) throw InputError("a symmetry's point must be finite");
}

}  // namespace

Symmetry Symmetry::reflection(const Vec3& point, const Vec3& normal) {
  check_point(point);
  Symmetry s;
  s.kind = SymmetryKind::Reflection;
  s.point = point;
  s.direction = unit(normal, "normal");
  s.order = 2;
  return s;
}

Symmetry Symmetry::rotation(const Vec3& point, const Vec3& axis, int order) {
  check_point(point);
  if (order < 2 || order > kMaxRotationOrder)
    throw InputError("a rotation's order must be within 2.." + std::to_string(kMaxRotationOrder) + ", got " +
                     std::to_string(order));
  Symmetry s;
  s.kind = SymmetryKind::Rotation;
  s.point = point;
  s.direction = unit(axis, "axis");
  s.order = order;
  return s;
}

Eigen::Matrix3d Symmetry::linear(int k) const {
  if (kind == SymmetryKind::Reflection) {
    // A reflection is its own inverse: even powers are the identity.
    if (k % 2 == 0) return Eigen::Matrix3d::Identity();
    return Eigen::Matrix3d::Identity() - 2.0 * direction * direction.transpose();
  }
  const double angle = 2.0 * M_PI * static_cast<double>(k % order) / static_cast<double>(order);
  return Eigen::AngleAxisd(angle, direction).toRotationMatrix();
}

Vec3 Symmetry::map_point(const Vec3& p, int k) const { return point + linear(k) * (p - point); }

Vec3 Symmetry::map_direction(const Vec3& d, int k) const { return linear(k) * d; }

}  // namespace stripweave
