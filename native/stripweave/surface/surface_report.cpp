#include "stripweave/surface/surface_report.h"

namespace stripweave {

int genus_from_euler(Index vertices, Index edges, Index faces, Index components, Index boundary_loops) {
  const Index chi = vertices - edges + faces;
  return static_cast<int>((2 * components - boundary_loops - chi) / 2);
}

SurfaceReport surface_report(const Surface& s) {
  SurfaceReport r;
  r.vertices = s.mesh.num_vertices();
  r.triangles = s.mesh.num_triangles();
  r.components = s.components;
  r.genus = s.genus;
  r.boundary_loops = static_cast<Index>(s.boundary_loops.size());
  r.feature_curves = static_cast<Index>(s.feature_curves.size());
  r.feature_edges = s.feature_edge_count();
  r.brep_faces = s.brep_faces;
  r.bbox_diagonal = s.similarity.scale;
  r.warnings = s.warnings;
  return r;
}

}  // namespace stripweave
