// Isotropic remeshing to a target edge length (CGAL
// Polygon_mesh_processing::isotropic_remeshing adapter).
//
// Inputs
//   mesh                 clean, oriented manifold mesh
//   patch_of_triangle    per triangle, a patch id (the source B-rep face, or 0
//                        for all of a plain mesh). Edges between different
//                        patches are kept as constrained polylines, so each
//                        output triangle still belongs to exactly one patch.
//   constrained_edges    further edges to keep as polylines (sharp features,
//                        open boundaries); they may be split, never flipped or
//                        collapsed across.
//   constrained_vertices vertices that must not move or vanish (B-rep
//                        corners, feature curve ends).
//   target_edge_length   in the mesh's units
//   iterations           CGAL remeshing iterations (3 is usually enough)
// Outputs
//   RemeshResult::mesh                 the remeshed, still oriented mesh
//   RemeshResult::patch_of_triangle    per output triangle
//   RemeshResult::constrained_edges    output edges lying on input constrained
//                                      edges, on patch borders or on the mesh
//                                      boundary
//   RemeshResult::constrained_vertices the input constrained vertices' new ids
//   RemeshResult::source_vertex        per output vertex: the input vertex id it
//                                      was, or kInvalid for a new vertex
//
// Vertices are relaxed tangentially and reprojected onto the input patch they
// lie in; callers that have an exact surface project them again onto it.
// Patch borders and the boundary are always kept as polylines, and their
// corners (three or more of them meeting, or a polyline end) survive even when
// not listed; a bend inside one polyline survives only if listed.
// Topology (genus, boundary loops, components) and orientation are preserved.
// Throws InputError for a non-manifold or inconsistently oriented input,
// std::invalid_argument for arguments that do not fit the mesh.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

namespace stripweave {

struct RemeshResult {
  TriangleMesh mesh;
  std::vector<Index> patch_of_triangle;
  std::vector<EdgeKey> constrained_edges;
  std::vector<Index> constrained_vertices;
  std::vector<Index> source_vertex;
};

RemeshResult remesh_isotropic(const TriangleMesh& mesh, const std::vector<Index>& patch_of_triangle,
                              const std::vector<EdgeKey>& constrained_edges,
                              const std::vector<Index>& constrained_vertices, double target_edge_length,
                              int iterations = 3);

}  // namespace stripweave
