// Crease conformity of a primal layout (issue 17): how much of the crease
// network lies on primal edges, and crease paths inside a region, which the
// edges across crease exits follow (primal_edges.cpp).
#include "stripweave/layout/primalization.h"

#include <algorithm>
#include <queue>
#include <unordered_map>

namespace stripweave {

double refined_crease_length(const LoopArrangement& A, const std::vector<std::uint8_t>& refined_crease) {
  double total = 0;
  for (Index e = 0; e < A.topology.num_edges(); ++e)
    if (refined_crease[e]) total += (A.mesh.positions[A.topology.edges[e][0]] - A.mesh.positions[A.topology.edges[e][1]]).norm();
  return total;
}

void measure_crease_conformity(const PrimalContext& ctx, QuadLayout& layout) {
  const MeshTopology& rt = ctx.arrangement.topology;
  std::vector<std::uint8_t> on_edge(rt.num_edges(), 0);
  for (const PrimalEdge& pe : layout.edges)
    for (size_t i = 0; i + 1 < pe.path.size(); ++i) {
      const Index e = rt.find_edge(pe.path[i], pe.path[i + 1]);
      if (e != kInvalid) on_edge[e] = 1;
    }
  double total = 0, covered = 0;
  for (Index e = 0; e < rt.num_edges(); ++e) {
    if (!ctx.edge_feature[e]) continue;
    total += ctx.edge_length[e];
    covered += on_edge[e] ? ctx.edge_length[e] : 0.0;
  }
  layout.crease_off_edges = total - covered;
  layout.crease_conformity = total > 0 ? covered / total : 1.0;
  bool crease_regions = false;
  for (const Region& r : ctx.regions.regions) crease_regions |= r.colour == RegionColour::Crease;
  layout.crease_conforming = !crease_regions && layout.crease_off_edges <= kCreaseSlack;
}

std::vector<Index> crease_path_in_region(const PrimalContext& ctx, Index r, Index from, Index to) {
  const LoopArrangement& A = ctx.arrangement;
  const MeshTopology& rt = A.topology;
  // Breadth-first over the region's crease edges (a tree when the region
  // conforms, so the path is unique). The predecessors are kept per visited
  // vertex only: this runs per crease exit in every layout, the weave's
  // predicted ones included, and visits a crease path, not the mesh.
  std::unordered_map<Index, Index> pred{{from, from}};
  std::queue<Index> queue;
  queue.push(from);
  while (!queue.empty() && !pred.count(to)) {
    const Index v = queue.front();
    queue.pop();
    if (v != from && ctx.vertex_on_loop[v]) continue;  // an exit: the region ends here
    for (const Index* n = rt.vertex_neighbours.begin(v); n != rt.vertex_neighbours.end(v); ++n) {
      const Index e = rt.find_edge(v, *n);
      if (!ctx.edge_feature[e] || A.on_loop(e) || pred.count(*n)) continue;
      if (ctx.regions.triangle_region[rt.edge_triangles[e][0]] != r) continue;
      pred.emplace(*n, v);
      queue.push(*n);
    }
  }
  if (!pred.count(to)) return {};
  std::vector<Index> path{to};
  while (path.back() != from) path.push_back(pred[path.back()]);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace stripweave
