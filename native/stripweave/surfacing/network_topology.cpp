#include "stripweave/surfacing/network_topology.h"

#include "stripweave/core/error.h"
#include "stripweave/core/sort_unique.h"


namespace stripweave {

std::string side_name(Index patch, int side) {
  return "side " + std::to_string(side) + " of patch " + std::to_string(patch);
}

NetworkTopology network_topology(const PatchNetwork& network) {
  const Index nE = static_cast<Index>(network.edges.size());
  const Index nP = static_cast<Index>(network.patches.size());
  const Index nV = static_cast<Index>(network.vertices.size());
  for (Index e = 0; e < nE; ++e) {
    const NetworkEdge& E = network.edges[e];
    if (E.v0 < 0 || E.v0 >= nV || E.v1 < 0 || E.v1 >= nV)
      throw InputError("network edge " + std::to_string(e) + " names a vertex that does not exist");
    if (E.points.size() < 2) throw InputError("network edge " + std::to_string(e) + " has fewer than 2 points");
  }
  NetworkTopology t;
  t.uses.assign(nE, {});
  for (Index p = 0; p < nP; ++p)
    for (int s = 0; s < 4; ++s) {
      const Index e = network.patches[p].edges[s];
      if (e < 0 || e >= nE) throw InputError(side_name(p, s) + " names an edge that does not exist");
      t.uses[e].push_back({p, s, network.patches[p].reversed[s]});
      if (t.uses[e].size() > 2) throw InputError("network edge " + std::to_string(e) + " bounds more than two patch sides");
    }

  std::vector<std::vector<Index>> vertex_patches(nV), patch_vertices(nP);
  for (Index p = 0; p < nP; ++p) {
    for (Index e : network.patches[p].edges)
      for (Index v : {network.edges[e].v0, network.edges[e].v1}) patch_vertices[p].push_back(v);
    sort_unique(patch_vertices[p]);
    for (Index v : patch_vertices[p]) vertex_patches[v].push_back(p);
  }
  t.neighbours.assign(nP, {});
  for (Index p = 0; p < nP; ++p) {
    for (Index v : patch_vertices[p])
      for (Index q : vertex_patches[v])
        if (q != p) t.neighbours[p].push_back(q);
    sort_unique(t.neighbours[p]);
  }
  return t;
}

}  // namespace stripweave
