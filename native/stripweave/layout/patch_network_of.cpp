// The quad layout as a patch network (see the header).
#include "stripweave/layout/patch_network_of.h"

#include <unordered_map>

namespace stripweave {

namespace {

// Whether the patch goes to the surfacing stage: a quad that does not fold
// back around a slit (its fit would be folded) and whose four sides are
// edges with a path of two points or more (a side collapsed to one point
// leaves two corners on one point, and has no curve to fit).
bool handed_over(const PrimalPatch& p, const QuadLayout& L) {
  if (!p.quad || p.folds_back()) return false;
  for (Index e : p.edges)
    if (e < 0 || e >= static_cast<Index>(L.edges.size()) || L.edges[e].path.size() < 2) return false;
  return true;
}

}  // namespace

PatchNetwork patch_network_of(const Surface& s, const LoopArrangement& A, const QuadLayout& L) {
  PatchNetwork net;
  const Similarity& sim = s.similarity;
  const BoundingBox box = bounding_box(s.mesh.positions);
  net.bbox_diagonal = box.diagonal() * sim.scale;
  for (const PrimalVertex& v : L.vertices) net.vertices.push_back(sim.to_model(v.position));
  // The edges the handed-over patches use, in the layout's order: an edge no
  // such patch has as a side (a dangling edge, the sides of left-out patches)
  // is no seam of the network, and one whose path is a single point (two
  // primal vertices on one refined vertex) has no curve to fit.
  std::vector<Index> network_edge(L.edges.size(), kInvalid);
  for (const PrimalPatch& p : L.patches)
    if (handed_over(p, L))
      for (Index e : p.edges) network_edge[e] = 0;
  for (Index e = 0; e < static_cast<Index>(L.edges.size()); ++e) {
    if (network_edge[e] == kInvalid) continue;
    network_edge[e] = static_cast<Index>(net.edges.size());
    const PrimalEdge& E = L.edges[e];
    NetworkEdge ne;
    for (Index v : E.path) ne.points.push_back(sim.to_model(L.positions[v]));
    ne.v0 = E.v0, ne.v1 = E.v1;
    ne.sharp = E.sharp, ne.boundary = E.boundary;
    net.edges.push_back(std::move(ne));
  }
  for (const PrimalPatch& p : L.patches) {
    if (!handed_over(p, L)) continue;
    NetworkPatch np;
    for (int k = 0; k < 4; ++k) np.edges[k] = network_edge[p.edges[k]];
    np.reversed = p.reversed;
    std::unordered_map<Index, Index> local;  // patch wedge -> patch-mesh vertex
    auto vertex_of = [&](Index wedge) {
      const auto [it, fresh] = local.emplace(wedge, np.mesh.num_vertices());
      if (fresh) np.mesh.positions.push_back(sim.to_model(L.positions[L.patch_wedges.vertex[wedge]]));
      return it->second;
    };
    for (Index t : p.triangles) {
      Tri f;
      for (int i = 0; i < 3; ++i) f[i] = vertex_of(L.patch_wedges.of(t, i));
      np.mesh.triangles.push_back(f);
      const Index parent = A.parent_triangle[t];
      np.source_face.push_back(s.brep && parent < static_cast<Index>(s.source_face.size()) ? s.source_face[parent]
                                                                                           : kInvalid);
    }
    for (int k = 0; k < 4; ++k) np.corners[k] = vertex_of(p.corner_wedges[k]);
    net.patches.push_back(std::move(np));
  }
  return net;
}

}  // namespace stripweave
