// See corner_strength.h.
#include "stripweave/surface/corner_strength.h"

#include "stripweave/surface/angle_defects.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

std::vector<double> corner_strength(const Surface& s, const std::vector<std::uint8_t>& crease) {
  const Index nv = s.mesh.num_vertices();
  const std::vector<double> defect = angle_defects(s.mesh, s.topology);
  std::vector<int> features(nv, 0);
  std::vector<std::uint8_t> boundary(nv, 0);
  for (Index e = 0; e < s.topology.num_edges(); ++e) {
    for (Index v : s.topology.edges[e]) {
      features[v] += crease[e];
      boundary[v] |= s.topology.is_boundary_edge(e);
    }
  }
  std::vector<double> strength(nv, 0.0);
  for (Index v = 0; v < nv; ++v) {
    if (boundary[v]) {
      if (std::abs(defect[v]) > kCornerTurn) strength[v] = std::abs(defect[v]);
      else if (features[v] >= 1) strength[v] = std::max(std::abs(defect[v]), 1e-3);
    } else if (features[v] >= 3) {
      strength[v] = std::max(std::abs(defect[v]), 1e-3);
    }
  }
  return strength;
}

}  // namespace stripweave
