// sanitize_mesh: turn a raw triangle soup into a clean, oriented manifold mesh,
// or say clearly why it cannot be one.
//
// Input : a TriangleMesh as read from a file or given as arrays.
// Output: the cleaned mesh, plus a warning line for every repair made, each
//         with its count.
//
// Errors (InputError):
//   - no triangles, or a triangle index out of range
//   - NaN or infinite coordinates
//   - an edge shared by more than two triangles (non-manifold edge)
//   - a non-orientable surface (Moebius-like)
// Documented repairs (warnings):
//   - outlier vertices (outlier_vertices.h) are removed with their triangles
//   - coincident vertices are welded (STL stores none shared; not a warning)
//   - triangles with a repeated vertex are removed
//   - zero-area triangles are removed by flipping their longest edge
//   - duplicate triangles (same three vertices) are removed
//   - pinched (non-manifold) vertices are split, one copy per fan
//   - inconsistently oriented triangles are flipped; closed components are
//     oriented outward
//   - unreferenced vertices are dropped
//   - tiny disconnected pieces (under `debris_fraction` of the area) are
//     dropped; several real components are kept and reported
#pragma once

#include "stripweave/surface/triangle_mesh.h"

#include <string>

namespace stripweave {

struct SanitizedMesh {
  TriangleMesh mesh;
  std::vector<std::string> warnings;
};

SanitizedMesh sanitize_mesh(const TriangleMesh& raw, double debris_fraction = 1e-3);

}  // namespace stripweave
