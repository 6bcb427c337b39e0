// Coarsening a dense mesh before remeshing it: the solver proxy of a scan
// (paper §8.1) in time proportional to the input (CGAL
// Surface_mesh_simplification adapter).
//
// simplify_short_edges(mesh, constrained_edges, constrained_vertices, min_edge)
//   Collapses edges shorter than min_edge, shortest first, each to its
//   midpoint, while the collapse keeps the topology (link condition) and turns
//   no triangle's normal by more than 90 degrees. Constrained edges (features,
//   open boundaries) are never collapsed and their vertices, like the listed
//   constrained vertices, never move: the feature polylines and the boundary
//   keep the input's vertices, and the remesher coarsens them afterwards.
// Inputs: a clean oriented manifold mesh; edges and vertices by input index.
// Outputs: the coarse mesh, its constrained edges (the surviving constrained
//   ones and the boundary) and the new ids of the constrained vertices.
// Isotropic remeshing straight from a million triangles to 30K spent most of
// a minute collapsing; collapsing first to about four times the target takes
// a few seconds and leaves the remesher a mesh near its size.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

namespace stripweave {

struct SimplifyResult {
  TriangleMesh mesh;
  std::vector<EdgeKey> constrained_edges;
  std::vector<Index> constrained_vertices;
};

SimplifyResult simplify_short_edges(const TriangleMesh& mesh, const std::vector<EdgeKey>& constrained_edges,
                                    const std::vector<Index>& constrained_vertices, double min_edge);

}  // namespace stripweave
