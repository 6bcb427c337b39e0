// Wedges: the vertices of a mesh cut open along a set of its edges.
//
// cut_wedges(mesh, topology, is_cut) -> Wedges
//   Input : a manifold triangle mesh, its topology, and a predicate telling
//           which edges are cut (loops, the primal edges, ...).
//   Output: per triangle corner (3 t + i) its wedge: the corners of one
//           vertex that are joined through uncut edges at it share a wedge.
//           A vertex away from every cut is one wedge; a vertex on a cut
//           curve is one wedge per side; a vertex where k cut edges meet is
//           k wedges. A wedge is the vertex of the cut-open mesh, so paths
//           over wedges stay on one side of every cut. Linear time.
#pragma once

#include "stripweave/surface/mesh_topology.h"

#include <functional>

namespace stripweave {

struct Wedges {
  std::vector<Index> corner_wedge;  // per corner 3 t + i
  std::vector<Index> vertex;        // per wedge: its mesh vertex
  Index count() const { return static_cast<Index>(vertex.size()); }
  Index of(Index t, int i) const { return corner_wedge[3 * static_cast<size_t>(t) + i]; }
};

Wedges cut_wedges(const TriangleMesh& mesh, const MeshTopology& topology, const std::function<bool(Index)>& is_cut);

// The corner of triangle t at vertex v (0, 1, 2), or -1.
inline int corner_of(const TriangleMesh& mesh, Index t, Index v) {
  const Tri& f = mesh.triangles[t];
  return f[0] == v ? 0 : f[1] == v ? 1 : f[2] == v ? 2 : -1;
}

}  // namespace stripweave
