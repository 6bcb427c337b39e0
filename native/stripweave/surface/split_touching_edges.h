// split_touching_edges: where two B-rep faces touch without sharing an edge,
// keep the welded tessellation edge-manifold.
//
// BRepMesh triangulates every face on its own. Two faces that meet only at
// two vertices (two tangent cylinders touching along a line that no B-rep
// edge follows, valid for OpenCASCADE's checker) may each join those two
// vertices by one interior mesh edge; welding the faces along their shared
// vertices then makes that edge a fin of four triangles, which no later
// stage can walk.
//
// split_touching_edges(mesh, face_of_triangle) -> number of edges split
//   Input : the welded tessellation and the B-rep face of every triangle.
//   For every edge used by more than two triangles, the uses are grouped by
//   face. Faces that have the edge on their border (one triangle) keep it,
//   as does the first face (lowest id) using it inside when no face has it
//   on its border; every other face's triangles at the edge are split at the
//   edge's midpoint, a new vertex of their own. The faces then touch at the
//   two vertices only, and the edge has at most two triangles (a rare edge
//   with three or more border uses is left to the manifold check, which
//   names it).
//   Output: the mesh and face_of_triangle, modified in place (new vertices
//   appended, each split triangle replaced by two of the same face and
//   orientation); the count of edges split.
//   Cost  : linear in the triangles.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

#include <vector>

namespace stripweave {

Index split_touching_edges(TriangleMesh& mesh, std::vector<Index>& face_of_triangle);

Index part_touching_faces(TriangleMesh& mesh, std::vector<Index>& face_of_triangle, std::vector<EdgeKey>& segments,
                          std::vector<Index>& corners);

}  // namespace stripweave
