// Crowded vertices (primalization.h; star_refinement.h): where the routed
// primal edges still share vertices, the refined mesh is too coarse for them.
// Routing (primal_edges.cpp) already tried every way around, so a vertex two
// edges pass after it is one the corridor cannot do without:
//   - a primal vertex is crowded when one of its edges leaves it through a
//     neighbour another edge also passes: too few free neighbours for its
//     edges (a valence-8 vertex among 6 neighbours);
//   - a vertex two edges pass is crowded itself: the corridor there is one
//     vertex wide (behind a boundary corner of degree 2 every edge into the
//     part passes the same vertex).
// Refining around both gives the edges room to pass apart; vertices on the
// loops stay as they are (an edge crosses its arc there).
#include "stripweave/layout/primalization.h"

#include "stripweave/core/sort_unique.h"

namespace stripweave {

std::vector<Index> crowded_vertices(const PrimalContext& ctx, const std::vector<PrimalVertex>& vertices,
                                           const std::vector<PrimalEdge>& edges) {
  // Per refined vertex, the primal edges through it (ends excluded).
  std::vector<Index> use(ctx.arrangement.mesh.num_vertices(), 0);
  for (const PrimalEdge& e : edges)
    for (size_t i = 1; i + 1 < e.path.size(); ++i) ++use[e.path[i]];
  std::vector<Index> crowded;
  auto check = [&](Index primal, Index first) {
    if (primal == kInvalid || use[first] < 2) return;
    const Index v = vertices[primal].refined_vertex;
    if (v != kInvalid && !ctx.vertex_on_loop[v]) crowded.push_back(v);
  };
  for (const PrimalEdge& e : edges) {
    const size_t n = e.path.size();
    if (n < 3) continue;
    check(e.v0, e.path[1]);
    check(e.v1, e.path[n - 2]);
  }
  for (Index v = 0; v < static_cast<Index>(use.size()); ++v)
    if (use[v] >= 2 && !ctx.vertex_on_loop[v]) crowded.push_back(v);
  sort_unique(crowded);
  return crowded;
}

}  // namespace stripweave
