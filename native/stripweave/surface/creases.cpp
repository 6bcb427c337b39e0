// See creases.h.
#include "stripweave/surface/creases.h"

#include <algorithm>

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
  // Networks of curves joined at their ends (junctions), and the longest curve of each.
  const Index nc = static_cast<Index>(s.feature_curves.size());
  std::vector<Index> parent(s.mesh.num_vertices());
  for (Index v = 0; v < s.mesh.num_vertices(); ++v) parent[v] = v;
  auto root = [&](Index v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (Index c = 0; c < nc; ++c) {
    const FeatureCurve& f = s.feature_curves[c];
    if (f.vertices.size() > 1) parent[root(f.vertices.front())] = root(f.vertices.back());
  }
  std::vector<double> longest(s.mesh.num_vertices(), 0.0);
  for (Index c = 0; c < nc; ++c)
    if (!s.feature_curves[c].vertices.empty()) {
      double& l = longest[root(s.feature_curves[c].vertices.front())];
      l = std::max(l, curve_length[c]);
    }
  for (Index e = 0; e < ne; ++e) {
    if (s.edge_class[e] != EdgeClass::Feature) continue;
    const Index c = e < static_cast<Index>(s.edge_curve.size()) ? s.edge_curve[e] : kInvalid;
    crease[e] = s.brep || c == kInvalid ||
                (curve_length[c] >= kMinCreaseLength && longest[root(s.feature_curves[c].vertices.front())] >= kMinCreaseSpan);
  }
  return crease;
}

}  // namespace stripweave
