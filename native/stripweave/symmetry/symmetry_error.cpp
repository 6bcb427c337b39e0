#include "stripweave/symmetry/symmetry_error.h"

#include <cmath>

namespace stripweave {

SymmetryError symmetry_error(const Symmetry& symmetry, const std::vector<Vec3>& samples, const SurfaceLocator& locator,
                             double give_up, bool keep_pairs) {
  SymmetryError out;
  if (keep_pairs) out.closest.reserve(samples.size());
  double sum2 = 0;
  for (const Vec3& p : samples) {
    // No hint from the previous answer: a far hint makes CGAL's search slower
    // than its own nearest-neighbour start (measured 3x on a remeshed part).
    const SurfacePoint3 at = locator.closest(symmetry.map_point(p));
    const double d = at.distance;
    if (keep_pairs) out.closest.push_back(at.point);
    sum2 += d * d;
    if (d > out.max) out.max = d;
    if (d > give_up) {
      out.complete = false;
      out.rms = std::sqrt(sum2 / static_cast<double>(samples.size()));
      return out;
    }
  }
  out.rms = samples.empty() ? 0.0 : std::sqrt(sum2 / static_cast<double>(samples.size()));
  return out;
}

}  // namespace stripweave
