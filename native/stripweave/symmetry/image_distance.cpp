#include "stripweave/symmetry/image_distance.h"

#include <algorithm>
#include <limits>

namespace stripweave {

namespace {

double point_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

}  // namespace

double image_distance(const Symmetry& symmetry, int k, const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.empty() || b.empty()) return std::numeric_limits<double>::infinity();
  double worst = 0;
  for (const Vec3& p : a) {
    const Vec3 q = symmetry.map_point(p, k);
    double best = (q - b.front()).norm();
    for (std::size_t i = 1; i < b.size(); ++i) best = std::min(best, point_segment(q, b[i - 1], b[i]));
    worst = std::max(worst, best);
  }
  return worst;
}

}  // namespace stripweave
