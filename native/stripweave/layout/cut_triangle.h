// cut_triangle: a triangle cut through midpoints of its sides, the pattern
// both refinements of the arrangement's mesh use (star_refinement.h splits
// the link edges of crowded vertices; loop_arrangement.cpp splits arcs of a
// single edge).
//
// cut_triangle(f, mid) -> pieces
//   Input : triangle f = (v0, v1, v2) and, per side i (from v_i to v_{i+1}),
//           the new vertex on it, or kInvalid where the side is not split.
//   Output: the pieces, counter-clockwise like f. One split side: two
//           pieces; two: the corner between them cut off, then the rest in
//           two; three: the four of a midpoint subdivision; none: f.
//
// cut_triangles(mesh, topology, mid) -> per new triangle, its source
//   Every triangle with a side carrying a new vertex (mid: per edge of
//   `topology`, the mesh's topology before the cut, kInvalid where not
//   split) is cut by cut_triangle; its first piece keeps its index and the
//   others are appended. Returns, per appended triangle, the triangle it was
//   cut from (for the caller's per-triangle arrays). The topology is stale
//   afterwards: the caller rebuilds it.
#pragma once

#include "stripweave/core/types.h"
#include "stripweave/surface/mesh_topology.h"

#include <array>
#include <vector>

namespace stripweave {

std::vector<Tri> cut_triangle(const Tri& f, const std::array<Index, 3>& mid);

std::vector<Index> cut_triangles(TriangleMesh& mesh, const MeshTopology& topology, const std::vector<Index>& mid);

}  // namespace stripweave
