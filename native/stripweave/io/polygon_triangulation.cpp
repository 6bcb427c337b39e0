#include "stripweave/io/polygon_triangulation.h"

#include <Eigen/Dense>

namespace stripweave {

namespace {

using Vec2 = Eigen::Vector2d;

double cross2(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

// Corner projections onto the plane of the Newell normal, so the polygon
// winds counter-clockwise there.
std::vector<Vec2> planar(const std::vector<Vec3>& positions, const std::vector<Index>& corners) {
  Vec3 n = Vec3::Zero();
  for (std::size_t i = 0; i < corners.size(); ++i)
    n += positions[corners[i]].cross(positions[corners[(i + 1) % corners.size()]]);
  if (n.norm() == 0) n = Vec3::UnitZ();
  n.normalize();
  const Vec3 u = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  const Vec3 v = n.cross(u);
  std::vector<Vec2> p;
  for (Index c : corners) p.emplace_back(positions[c].dot(u), positions[c].dot(v));
  return p;
}

// i is an ear of the remaining polygon: a convex corner whose triangle holds
// no other remaining corner (on its edges counts as inside, so a polygon that
// touches itself is not cut through the touching point).
bool is_ear(const std::vector<Vec2>& p, const std::vector<std::size_t>& left, std::size_t i, double tol) {
  const std::size_t m = left.size();
  const Vec2 &a = p[left[(i + m - 1) % m]], &b = p[left[i]], &c = p[left[(i + 1) % m]];
  if (cross2(a, b, c) <= tol) return false;
  for (std::size_t k = 0; k < m; ++k) {
    if (k == i || k == (i + 1) % m || k == (i + m - 1) % m) continue;
    const Vec2& q = p[left[k]];
    if (q == a || q == b || q == c) continue;
    if (cross2(a, b, q) >= -tol && cross2(b, c, q) >= -tol && cross2(c, a, q) >= -tol) return false;
  }
  return true;
}

// Two segments meet (cross or touch).
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double d1 = cross2(c, d, a), d2 = cross2(c, d, b), d3 = cross2(a, b, c), d4 = cross2(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  auto on = [](const Vec2& p, const Vec2& q, const Vec2& r, double side) {  // r on segment pq
    return side == 0 && r.x() >= std::min(p.x(), q.x()) && r.x() <= std::max(p.x(), q.x()) &&
           r.y() >= std::min(p.y(), q.y()) && r.y() <= std::max(p.y(), q.y());
  };
  return on(c, d, a, d1) || on(c, d, b, d2) || on(a, b, c, d3) || on(a, b, d, d4);
}

// No two edges that are not neighbours meet: ear clipping is exact only on a
// simple polygon (on a bow tie it still finds ears, and folds).
bool is_simple(const std::vector<Vec2>& p) {
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // neighbours across the start
      if (segments_meet(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n])) return false;
    }
  return true;
}

}  // namespace

bool triangulate_polygon(const std::vector<Vec3>& positions, const std::vector<Index>& corners, std::vector<Tri>& out) {
  if (corners.size() < 3) return true;  // no area: nothing to add
  if (corners.size() == 3) {
    out.push_back({corners[0], corners[1], corners[2]});
    return true;
  }
  const std::vector<Vec2> p = planar(positions, corners);
  if (!is_simple(p)) return false;
  double extent = 0;
  for (const Vec2& q : p) extent = std::max(extent, (q - p[0]).cwiseAbs().maxCoeff());
  const double tol = 1e-14 * extent * extent;
  std::vector<std::size_t> left(corners.size());
  for (std::size_t i = 0; i < left.size(); ++i) left[i] = i;
  while (left.size() > 3) {
    std::size_t ear = left.size();
    for (std::size_t i = 0; i < left.size() && ear == left.size(); ++i)
      if (is_ear(p, left, i, tol)) ear = i;
    if (ear == left.size()) {
      // Only collinear corners may remain (a zero-area sliver: sanitize_mesh
      // repairs it); a reflex corner left means rounding defeated the test.
      bool flat = true;
      for (std::size_t i = 0; i < left.size() && flat; ++i)
        flat = std::abs(cross2(p[left[(i + left.size() - 1) % left.size()]], p[left[i]],
                               p[left[(i + 1) % left.size()]])) <= tol;
      if (!flat) return false;
      ear = 0;
    }
    const std::size_t m = left.size();
    out.push_back({corners[left[(ear + m - 1) % m]], corners[left[ear]], corners[left[(ear + 1) % m]]});
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(ear));
  }
  out.push_back({corners[left[0]], corners[left[1]], corners[left[2]]});
  return true;
}

}  // namespace stripweave
