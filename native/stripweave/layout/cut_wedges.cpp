// Wedges of a cut-open mesh (see the header).
#include "stripweave/layout/cut_wedges.h"

#include <numeric>

namespace stripweave {

Wedges cut_wedges(const TriangleMesh& m, const MeshTopology& topo, const std::function<bool(Index)>& is_cut) {
  const size_t corners = 3 * static_cast<size_t>(m.num_triangles());
  std::vector<Index> parent(corners);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  auto unite = [&](Index a, Index b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  };
  // An uncut edge joins, at each of its two vertices, the corners of its two triangles.
  for (Index e = 0; e < topo.num_edges(); ++e) {
    const auto& et = topo.edge_triangles[e];
    if (et[1] == kInvalid || is_cut(e)) continue;
    for (Index v : topo.edges[e]) unite(3 * et[0] + corner_of(m, et[0], v), 3 * et[1] + corner_of(m, et[1], v));
  }
  Wedges w;
  w.corner_wedge.assign(corners, kInvalid);
  for (size_t c = 0; c < corners; ++c) {
    const Index r = find(static_cast<Index>(c));
    if (w.corner_wedge[r] == kInvalid) {
      w.corner_wedge[r] = w.count();
      w.vertex.push_back(m.triangles[r / 3][r % 3]);
    }
    w.corner_wedge[c] = w.corner_wedge[r];
  }
  return w;
}

}  // namespace stripweave
