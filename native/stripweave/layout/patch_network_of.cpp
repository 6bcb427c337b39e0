// The quad layout as a patch network (see the header).
#include "stripweave/layout/patch_network_of.h"

#include <unordered_map>

namespace stripweave {

PatchNetwork patch_network_of(const Surface& s, const LoopArrangement& A, const QuadLayout& L) {
  PatchNetwork net;
  const Similarity& sim = s.similarity;
  const BoundingBox box = bounding_box(s.mesh.positions);
  net.bbox_diagonal = box.diagonal() * sim.scale;
  for (const PrimalVertex& v : L.vertices) net.vertices.push_back(sim.to_model(v.position));
  for (const PrimalEdge& e : L.edges) {
    NetworkEdge ne;
    for (Index v : e.path) ne.points.push_back(sim.to_model(L.positions[v]));
    ne.v0 = e.v0, ne.v1 = e.v1;
    ne.sharp = e.sharp, ne.boundary = e.boundary;
    net.edges.push_back(std::move(ne));
  }
  for (const PrimalPatch& p : L.patches) {
    if (!p.quad) continue;
    NetworkPatch np;
    np.edges = p.edges;
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
