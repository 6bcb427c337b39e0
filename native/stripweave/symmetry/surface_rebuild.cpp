#include "stripweave/symmetry/surface_rebuild.h"

#include "stripweave/surface/feature_curves.h"
#include "stripweave/surface/surface_report.h"

namespace stripweave {

void rebuild_surface_structure(Surface& out, const std::function<bool(Index edge)>& is_feature,
                               const std::vector<bool>& end) {
  out.topology = MeshTopology::build(out.mesh);
  std::vector<Index> comp;
  out.components = triangle_components(out.topology, out.mesh.num_triangles(), comp);
  out.boundary_loops = boundary_loops(out.mesh, out.topology);
  out.genus = genus_from_euler(out.mesh.num_vertices(), out.topology.num_edges(), out.mesh.num_triangles(),
                               out.components, static_cast<Index>(out.boundary_loops.size()));
  std::vector<bool> feature(out.topology.num_edges(), false);
  for (Index e = 0; e < out.topology.num_edges(); ++e) feature[e] = !out.topology.is_boundary_edge(e) && is_feature(e);
  out.edge_class = classify_edges(out.topology, feature);
  out.feature_curves = chain_feature_curves(out.mesh, out.topology, out.edge_class, end, 0.0, out.edge_curve);
}

void carry_source(Surface& out, const Surface& s) {
  out.similarity = s.similarity;
  out.brep = s.brep;
  out.source_mesh = s.source_mesh;
  out.brep_faces = s.brep_faces;
  out.input_triangles = s.input_triangles;
  out.warnings = s.warnings;
  out.timings = s.timings;
}

double mean_edge_length(const Surface& s) {
  double sum = 0;
  for (const EdgeKey& e : s.topology.edges) sum += (s.mesh.positions[e[1]] - s.mesh.positions[e[0]]).norm();
  return s.topology.num_edges() ? sum / s.topology.num_edges() : 0.0;
}

std::vector<bool> feature_curve_ends(const Surface& s) {
  std::vector<bool> end(s.mesh.num_vertices(), false);
  for (const FeatureCurve& c : s.feature_curves)
    if (!c.closed && !c.vertices.empty()) end[c.vertices.front()] = end[c.vertices.back()] = true;
  return end;
}

}  // namespace stripweave
