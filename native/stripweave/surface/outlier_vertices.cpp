#include "stripweave/surface/outlier_vertices.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace stripweave {

namespace {

double median_of(std::vector<double> x) {
  const auto mid = x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2);
  std::nth_element(x.begin(), mid, x.end());
  return *mid;
}

// R: the radius about the per-axis median point that holds 95% of the
// referenced vertices. Distances are taken after scaling by the largest
// coordinate, so points near the double range do not overflow to infinity.
double core_radius(const TriangleMesh& m, const std::vector<bool>& used, Vec3& centre) {
  std::vector<double> axis[3], distance;
  for (Index v = 0; v < m.num_vertices(); ++v)
    if (used[v])
      for (int k = 0; k < 3; ++k) axis[k].push_back(m.positions[v][k]);
  for (int k = 0; k < 3; ++k) centre[k] = median_of(axis[k]);
  for (Index v = 0; v < m.num_vertices(); ++v)
    if (used[v]) distance.push_back((m.positions[v] - centre).stableNorm());
  const auto at = distance.begin() + static_cast<std::ptrdiff_t>(0.95 * (distance.size() - 1));
  std::nth_element(distance.begin(), at, distance.end());
  return *at;
}

}  // namespace

Index remove_outlier_vertices(TriangleMesh& m, Index* triangles_removed) {
  *triangles_removed = 0;
  std::vector<bool> used(m.positions.size(), false);
  for (const Tri& t : m.triangles)
    for (Index v : t) used[v] = true;
  Vec3 centre;
  const double reach = kOutlierReach * core_radius(m, used, centre);
  if (!(reach > 0) || !std::isfinite(reach)) return 0;  // all points coincide (refused later) or no core
  // Per vertex, its shortest edge.
  std::vector<double> shortest(m.positions.size(), std::numeric_limits<double>::infinity());
  for (const Tri& t : m.triangles)
    for (int i = 0; i < 3; ++i) {
      const Index a = t[i], b = t[(i + 1) % 3];
      const double len = (m.positions[a] - m.positions[b]).stableNorm();
      shortest[a] = std::min(shortest[a], len), shortest[b] = std::min(shortest[b], len);
    }
  std::vector<bool> outlier(m.positions.size(), false);
  Index count = 0;
  for (Index v = 0; v < m.num_vertices(); ++v)
    if (used[v] && shortest[v] > reach) outlier[v] = true, ++count;
  if (count == 0) return 0;
  std::vector<Tri> kept;
  kept.reserve(m.triangles.size());
  for (const Tri& t : m.triangles)
    if (!outlier[t[0]] && !outlier[t[1]] && !outlier[t[2]]) kept.push_back(t);
  *triangles_removed = static_cast<Index>(m.triangles.size() - kept.size());
  m.triangles.swap(kept);
  return count;
}

}  // namespace stripweave
