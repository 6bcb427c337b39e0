// Star refinement (star_refinement.h): split the link edges of crowded
// vertices, then carry every per-edge array over to the new edge numbering.
#include "stripweave/layout/star_refinement.h"

#include "stripweave/layout/cut_triangle.h"
#include "stripweave/layout/cut_wedges.h"

namespace stripweave {

namespace {

// The surface edge that the refined edge a-b runs along, or kInvalid when it
// crosses a surface triangle: both ends must lie on one surface edge (at its
// ends or inside it).
Index surface_edge_under(const Surface& s, const LoopArrangement& A, Index a, Index b) {
  auto on = [&](Index x, Index E) {
    if (A.original_edge[x] != kInvalid) return A.original_edge[x] == E;
    const Index o = A.original_vertex[x];
    return o != kInvalid && (s.topology.edges[E][0] == o || s.topology.edges[E][1] == o);
  };
  for (const Index x : {a, b}) {
    const Index E = A.original_edge[x];
    if (E != kInvalid) return on(a, E) && on(b, E) ? E : kInvalid;
  }
  const Index oa = A.original_vertex[a], ob = A.original_vertex[b];
  return oa == kInvalid || ob == kInvalid ? kInvalid : s.topology.find_edge(oa, ob);
}

// The triangle on edge e that holds the directed edge a -> b (kInvalid if none).
Index triangle_with(const TriangleMesh& m, const MeshTopology& t, Index e, Index a, Index b) {
  for (const Index tri : t.edge_triangles[e]) {
    if (tri == kInvalid) continue;
    const Tri& f = m.triangles[tri];
    for (int i = 0; i < 3; ++i)
      if (f[i] == a && f[(i + 1) % 3] == b) return tri;
  }
  return kInvalid;
}

// Every per-edge array of the arrangement and regions, from the old
// topology's numbering to the new one's (old_of_new: per new edge, the old
// edge with the same ends, kInvalid for a new edge).
void renumber_edges(const MeshTopology& old_topology, const std::vector<Index>& old_of_new, LoopArrangement& A,
                    Regions& G) {
  const Index ne = A.topology.num_edges();
  auto renumber = [&](std::vector<Index>& edges) {
    for (Index& e : edges) {
      const EdgeKey& k = old_topology.edges[e];
      e = A.topology.find_edge(k[0], k[1]);
    }
  };
  for (LoopChain& c : A.chains) renumber(c.edges);
  for (LoopArc& arc : A.arcs) {
    renumber(arc.edges);
    if (arc.edges.empty()) continue;
    const Index a = arc.vertices[0], b = arc.vertices[1 % arc.vertices.size()];
    if (arc.left_triangle != kInvalid) arc.left_triangle = triangle_with(A.mesh, A.topology, arc.edges[0], a, b);
    if (arc.right_triangle != kInvalid) arc.right_triangle = triangle_with(A.mesh, A.topology, arc.edges[0], b, a);
  }
  Csr labels;
  labels.offsets.assign(ne + 1, 0);
  std::vector<std::uint8_t> crease(ne, 0);
  for (Index e = 0; e < ne; ++e) {
    const Index o = old_of_new[e];
    labels.offsets[e + 1] = labels.offsets[e] + (o == kInvalid ? 0 : A.edge_labels.size(o));
    if (o != kInvalid) crease[e] = G.creases.refined_crease[o];
  }
  labels.indices.reserve(labels.offsets.back());
  for (Index e = 0; e < ne; ++e)
    if (old_of_new[e] != kInvalid)
      labels.indices.insert(labels.indices.end(), A.edge_labels.begin(old_of_new[e]), A.edge_labels.end(old_of_new[e]));
  A.edge_labels = std::move(labels);
  G.creases.refined_crease = std::move(crease);
}

}  // namespace

Index refine_stars(const Surface& s, LoopArrangement& A, Regions& G, const std::vector<Index>& centres) {
  const MeshTopology old = A.topology;
  TriangleMesh& m = A.mesh;

  // The link edges to split, and the vertex each gets.
  std::vector<Index> mid(old.num_edges(), kInvalid);
  Index split = 0;
  for (const Index c : centres) {
    for (const Index* t = old.vertex_triangles.begin(c); t != old.vertex_triangles.end(c); ++t) {
      const int i = corner_of(m, *t, c);
      const Index e = old.triangle_edges[*t][(i + 1) % 3];  // the side opposite c
      if (mid[e] != kInvalid || A.separates(e) || G.creases.refined_crease[e]) continue;
      const EdgeKey& k = old.edges[e];
      mid[e] = m.num_vertices();
      m.positions.push_back(0.5 * (m.positions[k[0]] + m.positions[k[1]]));
      A.original_vertex.push_back(kInvalid);
      A.original_edge.push_back(surface_edge_under(s, A, k[0], k[1]));
      A.degree.push_back(0);
      ++split;
    }
  }
  if (split == 0) return 0;

  // Cut every triangle with a split side; the first piece keeps its index.
  for (const Index t : cut_triangles(m, old, mid)) {
    A.parent_triangle.push_back(A.parent_triangle[t]);
    const Index r = G.triangle_region[t];
    G.triangle_region.push_back(r);
    if (r != kInvalid) ++G.regions[r].triangles;
  }

  A.topology = MeshTopology::build(m);
  std::vector<Index> old_of_new(A.topology.num_edges(), kInvalid);
  for (Index e = 0; e < old.num_edges(); ++e) {
    if (mid[e] != kInvalid) continue;
    const EdgeKey& k = old.edges[e];
    old_of_new[A.topology.find_edge(k[0], k[1])] = e;
  }
  renumber_edges(old, old_of_new, A, G);
  return split;
}

}  // namespace stripweave
