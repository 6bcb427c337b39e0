// Primal edges routed by hand (paper §7, manual: the user "draws layout
// edges dual to the loops", deciding "where within a dual loop corridor a
// patch boundary should lie"): which edge a route (EdgeRoute) takes, and
// the point of its corridor it goes through.
//
// Input   the primalization context, the regions' vertex wedges
//         (place_primal_vertices, after pins and symmetries), the routes
//         (normalized units) in the order the user made them.
// Output  per route that applies, the arc whose edge it takes and the wedge
//         the edge goes through; a problem line per route that does not.
// Rules   A route's `through` point lies in the region of the nearest
//         refined vertex off the loops (as a vertex pin's does): the edge
//         runs through that vertex. Its edge is the one dual to the arc
//         nearest its `across` point (the point where the edge crossed its
//         loop when the user grabbed it, which names the edge without
//         depending on the route it had) among the arcs of that region:
//         an edge lies in the corridor of its arc's two regions, so a point
//         outside them cannot be on it. An edge with no vertex at one end
//         takes no route. Of several routes of one edge the last counts.
// Cost    O(routes x (refined vertices + arc vertices)).
#include "stripweave/layout/primalization.h"

#include <algorithm>
#include <limits>

namespace stripweave {

std::vector<ResolvedEdgeRoute> resolve_edge_routes(const PrimalContext& ctx, const std::vector<Index>& vertex_wedge,
                                                   const std::vector<EdgeRoute>& routes,
                                                   std::vector<std::string>& problems) {
  const LoopArrangement& A = ctx.arrangement;
  const Index na = static_cast<Index>(A.arcs.size());
  std::vector<Index> last(na, kInvalid);  // per arc, the route that counts
  std::vector<ResolvedEdgeRoute> out;
  for (Index i = 0; i < static_cast<Index>(routes.size()); ++i) {
    const EdgeRoute& route = routes[i];
    const std::string which = "edge route " + std::to_string(i + 1);
    const Index w = nearest_wedge(ctx, route.through, [&](Index x) {
      const Index r = ctx.wedge_region[x];
      return r != kInvalid && vertex_wedge[r] != kInvalid && x != vertex_wedge[r];
    });
    if (w == kInvalid) {
      problems.push_back(which + ": no point of the layout's regions to route an edge through");
      continue;
    }
    const Index r = ctx.wedge_region[w];
    Index arc = kInvalid;
    double best = std::numeric_limits<double>::infinity();
    for (Index k = 0; k < na; ++k) {
      const Index L = ctx.regions.arc_left[k], R = ctx.regions.arc_right[k];
      if ((L != r && R != r) || L == kInvalid || R == kInvalid) continue;
      if (vertex_wedge[L] == kInvalid || vertex_wedge[R] == kInvalid) continue;
      for (Index v : A.arcs[k].vertices) {
        const double d = (A.mesh.positions[v] - route.across).squaredNorm();
        if (d < best) best = d, arc = k;
      }
    }
    if (arc == kInvalid) {
      problems.push_back(which + ": the point's region has no edge to route through it");
      continue;
    }
    if (last[arc] != kInvalid) out[last[arc]].arc = kInvalid;  // superseded
    last[arc] = static_cast<Index>(out.size());
    out.push_back({i, arc, w});
  }
  out.erase(std::remove_if(out.begin(), out.end(), [](const ResolvedEdgeRoute& r) { return r.arc == kInvalid; }),
            out.end());
  return out;
}

}  // namespace stripweave
