// See creases.h.
#include "stripweave/surface/creases.h"

namespace stripweave {

std::vector<std::uint8_t> creases_of(const Surface& s) {
  const Index ne = s.topology.num_edges();
  std::vector<std::uint8_t> crease(ne, 0);
  std::vector<double> curve_length(s.feature_curves.size(), 0.0);
  for (size_t c = 0; c < s.feature_curves.size(); ++c) {
    const FeatureCurve& f = s.feature_curves[c];
    for (size_t i = 0; i + 1 < f.vertices.size(); ++i)
      curve_length[c] += (s.mesh.positions[f.vertices[i + 1]] - s.mesh.positions[f.vertices[i]]).norm();
    if (f.closed && f.vertices.size() > 1)
      curve_length[c] += (s.mesh.positions[f.vertices.front()] - s.mesh.positions[f.vertices.back()]).norm();
  }
  for (Index e = 0; e < ne; ++e) {
    if (s.edge_class[e] != EdgeClass::Feature) continue;
    const Index c = e < static_cast<Index>(s.edge_curve.size()) ? s.edge_curve[e] : kInvalid;
    crease[e] = s.brep || c == kInvalid || curve_length[c] >= kMinCreaseLength;
  }
  return crease;
}

}  // namespace stripweave
