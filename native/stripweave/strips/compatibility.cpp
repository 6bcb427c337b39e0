// Strip compatibility (see compatibility.h).
#include "stripweave/strips/compatibility.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

std::vector<Index> incompatible_nodes(const Surface& surface, const ElasticaGraph& g, const Strip& strip,
                                      double max_angle_deg, double band) {
  // |cos| of the angle to the isocurve, either way along it.
  const double cos_limit = std::cos(max_angle_deg * M_PI / 180.0);
  // Per vertex, the least |across| of the strip there.
  std::vector<double> across(surface.mesh.num_vertices(), std::numeric_limits<double>::infinity());
  if (std::isfinite(band)) {
    for (size_t k = 0; k < strip.triangles.size(); ++k)
      for (int i = 0; i < 3; ++i) {
        double& a = across[surface.mesh.triangles[strip.triangles[k]][i]];
        a = std::min(a, std::abs(strip.coords[k][i].y()));
      }
  }
  std::vector<Index> nodes;
  for (Index v = 0; v < surface.mesh.num_vertices(); ++v) {
    const Vec3& iso = strip.isocurve[v];
    if (iso.squaredNorm() == 0) continue;
    if (std::isfinite(band) && across[v] > band) continue;
    for (Index n = g.node_offsets[v]; n < g.node_offsets[v + 1]; ++n) {
      if (std::abs(g.tangent(surface, n).dot(iso)) > cos_limit) {
        nodes.push_back(n);
        nodes.push_back(g.reverse[n]);
      }
    }
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

}  // namespace stripweave
