// See creases.h.
#include "stripweave/surface/creases.h"

#include <algorithm>

namespace stripweave {

namespace {

double curve_length(const TriangleMesh& mesh, const FeatureCurve& f) {
  double length = 0;
  for (size_t i = 0; i + 1 < f.vertices.size(); ++i)
    length += (mesh.positions[f.vertices[i + 1]] - mesh.positions[f.vertices[i]]).norm();
  if (f.closed && f.vertices.size() > 1)
    length += (mesh.positions[f.vertices.front()] - mesh.positions[f.vertices.back()]).norm();
  return length;
}

// Per curve, whether the crease rule keeps it (see the header).
std::vector<bool> crease_curves(const TriangleMesh& mesh, const std::vector<FeatureCurve>& curves) {
  const size_t nc = curves.size();
  std::vector<double> length(nc);
  for (size_t c = 0; c < nc; ++c) length[c] = curve_length(mesh, curves[c]);
  // Networks: curves joined at their ends (union-find over end vertices).
  std::vector<Index> parent(mesh.num_vertices());
  for (Index v = 0; v < mesh.num_vertices(); ++v) parent[v] = v;
  auto root = [&](Index v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const FeatureCurve& f : curves)
    if (f.vertices.size() > 1) parent[root(f.vertices.front())] = root(f.vertices.back());
  std::vector<double> longest(mesh.num_vertices(), 0.0);
  for (size_t c = 0; c < nc; ++c)
    if (!curves[c].vertices.empty()) {
      double& l = longest[root(curves[c].vertices.front())];
      l = std::max(l, length[c]);
    }
  std::vector<bool> keep(nc, false);
  for (size_t c = 0; c < nc; ++c)
    keep[c] = !curves[c].vertices.empty() && length[c] >= kMinCreaseLength &&
              longest[root(curves[c].vertices.front())] >= kMinCreaseSpan;
  return keep;
}

}  // namespace

void keep_crease_curves(const TriangleMesh& mesh, const MeshTopology& topo, std::vector<EdgeClass>& classes,
                        std::vector<FeatureCurve>& curves, std::vector<Index>& edge_curve) {
  const std::vector<bool> keep = crease_curves(mesh, curves);
  std::vector<Index> renumber(curves.size(), kInvalid);
  std::vector<FeatureCurve> kept;
  for (size_t c = 0; c < curves.size(); ++c)
    if (keep[c]) renumber[c] = static_cast<Index>(kept.size()), kept.push_back(std::move(curves[c]));
  for (Index e = 0; e < topo.num_edges(); ++e) {
    if (classes[e] != EdgeClass::Feature) continue;
    const Index c = edge_curve[e];
    edge_curve[e] = c == kInvalid ? kInvalid : renumber[c];
    if (edge_curve[e] == kInvalid) classes[e] = EdgeClass::Regular;
  }
  curves = std::move(kept);
}

std::vector<std::uint8_t> creases_of(const Surface& s) {
  std::vector<std::uint8_t> crease(s.topology.num_edges(), 0);
  for (Index e = 0; e < s.topology.num_edges(); ++e) crease[e] = s.edge_class[e] == EdgeClass::Feature;
  return crease;
}

}  // namespace stripweave
