// Symmetry: a global reflection or rotation of a surface (paper §5.8), the map
// psi that takes the representative part M0 onto the other parts M_i.
//
//   Symmetry::reflection(point, normal)      the plane through point with the
//                                            unit normal (normalized here)
//   Symmetry::rotation(point, axis, order)   rotation by 2 pi / order about
//                                            the line through point along the
//                                            unit axis; order 2..kMaxOrder
//   InputError for a zero or non-finite normal or axis, an order out of range.
//
//   map_point(p, k = 1), map_direction(d, k = 1)   psi^k (k may be negative:
//                                            the inverse); directions ignore
//                                            the point
//   inverse_point(p), inverse_direction(d)   psi^-1
//   images()                                 the group's non-identity
//                                            elements: 1 for a reflection,
//                                            order - 1 for a rotation
//   rms_error, max_error                     how far psi maps the surface off
//                                            itself (symmetry_error.h), in the
//                                            units of the surface it was
//                                            measured on; 0 until measured
// Plain geometry in whatever units the caller uses (normalized in the core,
// model units at the bindings).
#pragma once

#include "stripweave/core/types.h"

namespace stripweave {

enum class SymmetryKind : std::uint8_t { Reflection = 0, Rotation = 1 };

constexpr int kMaxRotationOrder = 64;

struct Symmetry {
  SymmetryKind kind = SymmetryKind::Reflection;
  Vec3 point = Vec3::Zero();
  Vec3 direction = Vec3::UnitX();  // the plane's normal or the rotation's axis, unit
  int order = 2;                   // 2 for a reflection
  double rms_error = 0;
  double max_error = 0;

  static Symmetry reflection(const Vec3& point, const Vec3& normal);
  static Symmetry rotation(const Vec3& point, const Vec3& axis, int order);

  Vec3 map_point(const Vec3& p, int k = 1) const;
  Vec3 map_direction(const Vec3& d, int k = 1) const;
  Vec3 inverse_point(const Vec3& p) const { return map_point(p, -1); }
  Vec3 inverse_direction(const Vec3& d) const { return map_direction(d, -1); }
  int images() const { return kind == SymmetryKind::Reflection ? 1 : order - 1; }
  // The linear part of psi^k.
  Eigen::Matrix3d linear(int k = 1) const;
};

}  // namespace stripweave
