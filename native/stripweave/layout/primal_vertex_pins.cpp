// Pinned primal vertices (paper §7: "the user can drag a primal vertex
// within its region"): after the rules of quad_layout.h have placed one
// vertex per region, each pin moves its region's vertex to the point of that
// region nearest the pin.
//
// Input   the primalization context, pins (normalized units), the placed
//         vertices and their wedges (place_primal_vertices).
// Output  the vertices of the pinned regions moved (placement Pinned, their
//         position, refined vertex, boundary flag and clearance updated) and
//         vertex_wedge with them; every vertex lists the pins in its region.
// Rules   A pin belongs to the region of the nearest refined vertex off the
//         loops: a region is where the user dropped the vertex. It moves the
//         vertex only among the points the placement rules allow there, so a
//         pinned layout stays what the unpinned one is made to be: a corner
//         of the part (a crease junction, a boundary corner) stays where it
//         is; a region on the open boundary keeps its vertex on the boundary
//         (so that primal edges cover the boundary), one carrying a crease
//         keeps it on the crease (so that the crease stays on primal edges);
//         elsewhere any point of the region off its loops (a vertex on a loop
//         would lie on its own dual edge). Of several pins in one region the
//         last counts.
// Cost    O(pins x refined vertices) to find the regions, and one shortest-
//         path search for the clearances when a pin moved a vertex.
#include "stripweave/layout/primalization.h"

#include <limits>

namespace stripweave {

Index nearest_wedge(const PrimalContext& ctx, const Vec3& p, const std::function<bool(Index)>& allowed) {
  const auto& positions = ctx.arrangement.mesh.positions;
  Index best = kInvalid;
  double best_d = std::numeric_limits<double>::infinity();
  for (Index w = 0; w < ctx.wedges.count(); ++w) {
    const Index v = ctx.wedges.vertex[w];
    if (ctx.vertex_on_loop[v] || ctx.vertex_crossing[v] || !allowed(w)) continue;
    const double d = (positions[v] - p).squaredNorm();
    if (d < best_d) best_d = d, best = w;
  }
  return best;
}

void pin_primal_vertices(const PrimalContext& ctx, const std::vector<Vec3>& pins, std::vector<PrimalVertex>& vertices,
                         std::vector<Index>& vertex_wedge) {
  if (pins.empty()) return;
  const std::vector<std::uint8_t> on_crease = crease_vertices(ctx);
  bool moved = false;
  for (Index i = 0; i < static_cast<Index>(pins.size()); ++i) {
    const Vec3& pin = pins[i];
    const Index dropped = nearest_wedge(ctx, pin, [](Index) { return true; });
    if (dropped == kInvalid) continue;
    const Index r = ctx.wedge_region[dropped];
    PrimalVertex& pv = vertices[r];
    pv.pins.push_back(i);
    const VertexPlacement rule = pv.placement;
    if (rule == VertexPlacement::Corner || vertex_wedge[r] == kInvalid) continue;
    const Index w = nearest_wedge(ctx, pin, [&](Index x) {
      const Index v = ctx.wedges.vertex[x];
      if (ctx.wedge_region[x] != r) return false;
      if (rule == VertexPlacement::Boundary) return ctx.vertex_on_boundary[v] != 0;
      if (rule == VertexPlacement::Feature) return on_crease[v] != 0;
      return true;
    });
    if (w == kInvalid) continue;
    vertex_wedge[r] = w;
    pv.placement = VertexPlacement::Pinned;
    pv.refined_vertex = ctx.wedges.vertex[w];
    pv.position = ctx.arrangement.mesh.positions[pv.refined_vertex];
    pv.boundary = ctx.vertex_on_boundary[pv.refined_vertex];
    moved = true;
  }
  if (!moved) return;
  // The moved vertices' distance from the loops (their region's inradius stays).
  const std::vector<double> clearance = loop_clearance(ctx);
  for (size_t r = 0; r < vertices.size(); ++r)
    if (vertices[r].placement == VertexPlacement::Pinned) vertices[r].clearance = clearance[vertex_wedge[r]];
}

}  // namespace stripweave
