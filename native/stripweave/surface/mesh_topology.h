// MeshTopology: edge-based connectivity of a manifold triangle mesh.
//
// Input : a TriangleMesh whose every edge has one or two triangles.
// Output (indexed by element):
//   edges[e]            the undirected edge, smaller vertex first
//   edge_triangles[e]   its (one or two) triangles; [1] == kInvalid on a boundary
//   triangle_edges[t]   edge i of triangle t joins its corners i and i+1 (mod 3)
//   vertex_triangles    CSR (offsets, indices): the triangles around vertex v
//   vertex_neighbours   CSR: the vertices joined to v by an edge
//
// build() throws InputError for an edge shared by more than two triangles,
// naming how many there are and where the first one is.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

#include <functional>
#include <unordered_map>

namespace stripweave {

// Compressed sparse rows: the items of row r are indices[offsets[r] .. offsets[r+1]).
struct Csr {
  std::vector<Index> offsets;
  std::vector<Index> indices;
  Index size(Index r) const { return offsets[r + 1] - offsets[r]; }
  const Index* begin(Index r) const { return indices.data() + offsets[r]; }
  const Index* end(Index r) const { return indices.data() + offsets[r + 1]; }
};

struct MeshTopology {
  std::vector<EdgeKey> edges;
  std::vector<std::array<Index, 2>> edge_triangles;
  std::vector<std::array<Index, 3>> triangle_edges;
  Csr vertex_triangles;
  Csr vertex_neighbours;

  static MeshTopology build(const TriangleMesh& mesh);

  Index num_edges() const { return static_cast<Index>(edges.size()); }
  bool is_boundary_edge(Index e) const { return edge_triangles[e][1] == kInvalid; }
  // The edge joining a and b, or kInvalid.
  Index find_edge(Index a, Index b) const;

 private:
  std::unordered_map<std::uint64_t, Index> edge_index_;
};

inline std::uint64_t pack_edge(const EdgeKey& k) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k[0])) << 32) |
         static_cast<std::uint32_t>(k[1]);
}

// Connected components over shared edges: per triangle, its component id
// (0..count-1). Returns count.
Index triangle_components(const MeshTopology& topo, Index num_triangles, std::vector<Index>& component);

// The same, not crossing the edges for which is_cut holds (the pieces of a
// mesh cut along loops, primal edges, ...). Numbered in the order of each
// piece's first triangle, like triangle_components.
Index triangle_components(const MeshTopology& topo, Index num_triangles, std::vector<Index>& component,
                          const std::function<bool(Index)>& is_cut);

// Boundary loops as closed vertex chains (first vertex not repeated),
// oriented like the triangles they bound.
std::vector<std::vector<Index>> boundary_loops(const TriangleMesh& mesh, const MeshTopology& topo);

// The fans around vertex v: triangles around v joined through edges at v
// share a fan. Returns, per triangle of vertex_triangles(v) in that order,
// its fan id (0..fans-1); `fans` receives the count.
std::vector<Index> vertex_fans(const MeshTopology& topo, Index v, Index& fans);

// Vertices whose triangle fan is not a single disc or half-disc (pinched
// vertices), each as the number of separate fans around it.
std::vector<std::pair<Index, Index>> non_manifold_vertices(const TriangleMesh& mesh, const MeshTopology& topo);

// Give every extra fan of a pinched vertex its own copy of the vertex (new
// vertices appended; `topo` is the mesh's before the split). Returns, per
// pinched vertex, its copies with the vertex itself first, fan 0 keeping it.
std::vector<std::vector<Index>> split_pinched_vertices(TriangleMesh& mesh, const MeshTopology& topo);

}  // namespace stripweave
