// Primal vertices: one per region (paper §7), placed by the rules of
// quad_layout.h. Why this order: a corner of the part (a boundary corner, a
// junction of creases) is where a CAD engineer expects a patch corner, and
// a patch corner anywhere else on it would leave a crease or a boundary
// kink inside a patch. A region touching the open boundary must put its
// vertex there so that the boundary is covered by primal edges. A region
// that a sharp feature curve runs through puts its vertex on the crease
// (the point of it where the sides balance), so that the primal edges can
// follow the crease to the neighbouring regions' vertices: a vertex off the
// crease leaves the crease inside its patches (a capped cylinder's "box"
// design would get cap-and-side patches folded over the rim, which no
// B-spline patch fits). Otherwise the region's one singularity is the irregular vertex the field asks for
// (a region of valence != 4 holds at least one), unless it lies closer to
// the loops than half the region's inradius; failing that the region's
// balanced centre (primal_vertex_balance.cpp), where the middles of its
// corridors cross, as the paper's crossing elastica curves do, among the
// points at least half as far from the loops as the farthest. On a crease
// or the boundary the vertex also takes the point where the sides balance.
#include "stripweave/layout/primalization.h"

#include "stripweave/surface/corner_strength.h"

#include <cmath>
#include <limits>

namespace stripweave {

Index wedge_at(const PrimalContext& ctx, Index v, Index r) {
  const LoopArrangement& A = ctx.arrangement;
  for (const Index* t = A.topology.vertex_triangles.begin(v); t != A.topology.vertex_triangles.end(v); ++t) {
    const Index w = ctx.wedges.of(*t, corner_of(A.mesh, *t, v));
    if (ctx.wedge_region[w] == r) return w;
  }
  return kInvalid;
}

std::vector<double> loop_clearance(const PrimalContext& ctx) {
  std::vector<Index> on_loops;
  for (Index w = 0; w < ctx.wedges.count(); ++w)
    if (ctx.vertex_on_loop[ctx.wedges.vertex[w]]) on_loops.push_back(w);
  return ctx.shortest_paths(
      on_loops, [&](Index e) { return ctx.edge_length[e]; }, [](Index) { return false; }, nullptr);
}

std::vector<std::uint8_t> crease_vertices(const PrimalContext& ctx) {
  const LoopArrangement& A = ctx.arrangement;
  std::vector<std::uint8_t> on(A.mesh.num_vertices(), 0);
  for (Index e = 0; e < A.topology.num_edges(); ++e)
    if (ctx.edge_feature[e])
      for (Index v : A.topology.edges[e]) on[v] = 1;
  return on;
}

std::vector<PrimalVertex> place_primal_vertices(const PrimalContext& ctx, const std::vector<Singularity>& singularities,
                                                std::vector<Index>& vertex_wedge) {
  const LoopArrangement& A = ctx.arrangement;
  const Index nr = static_cast<Index>(ctx.regions.regions.size());
  const Index nw = ctx.wedges.count();
  const std::vector<double> strength = corner_strength(ctx.surface, ctx.surface_crease);

  const std::vector<double> clearance = loop_clearance(ctx);

  // Where the region's sides balance (primal_vertex_balance.cpp): the
  // centre, and the point of a crease or the boundary a vertex goes to.
  const std::vector<double> balance = side_balance(ctx);

  // Candidates per region, each rule keeping its best wedge (largest value).
  // The rules in the order of VertexPlacement.
  enum { kCorner, kBoundary, kFeature, kSingularity, kCentre, kRules };
  std::vector<std::array<Index, kRules>> best(nr, {kInvalid, kInvalid, kInvalid, kInvalid, kInvalid});
  const double lowest = -std::numeric_limits<double>::infinity();
  std::vector<std::array<double, kRules>> score(nr, {lowest, lowest, lowest, lowest, lowest});
  // Per region the largest clearance, and the largest on a crease and on the boundary.
  std::vector<double> inradius(nr, 0.0), crease_clearance(nr, -1.0), boundary_clearance(nr, -1.0);
  const std::vector<std::uint8_t> on_feature = crease_vertices(ctx);
  for (Index w = 0; w < nw; ++w) {
    const Index v = ctx.wedges.vertex[w], r = ctx.wedge_region[w];
    if (ctx.vertex_on_loop[v]) continue;
    inradius[r] = std::max(inradius[r], clearance[w]);
    if (on_feature[v]) crease_clearance[r] = std::max(crease_clearance[r], clearance[w]);
    if (ctx.vertex_on_boundary[v]) boundary_clearance[r] = std::max(boundary_clearance[r], clearance[w]);
  }
  auto offer = [&](Index rule, Index w, double value) {
    const Index r = ctx.wedge_region[w];
    if (value > score[r][rule]) score[r][rule] = value, best[r][rule] = w;
  };
  const Index surface_vertices = ctx.surface.mesh.num_vertices();
  // Per region its crease point farthest from the loops: where a crease
  // region's vertex goes when no crease point is as centred as the rule asks.
  std::vector<Index> crease_far(nr, kInvalid);
  std::vector<double> crease_far_clearance(nr, -1.0);
  for (Index w = 0; w < nw; ++w) {
    const Index v = ctx.wedges.vertex[w];
    if (ctx.vertex_on_loop[v]) continue;  // a vertex on a loop would sit on its own dual edge
    const Index r = ctx.wedge_region[w];
    const Index sv = A.original_vertex[v];
    const double centred = -balance[w];  // offer keeps the largest
    if (sv != kInvalid && sv < surface_vertices && strength[sv] > 0) offer(kCorner, w, strength[sv]);
    // The sides balance only among the points at least half as far from the loops as the
    // farthest (of the region, of its crease, of its boundary): the least sum of squares
    // alone can sit next to a loop (a side cut into several arcs by crossings counts
    // each, and pulls the vertex towards it). On a crease running close to a loop, a
    // lofted box's rim vertices came in pairs a few units apart, and its patches no
    // longer fitted within tolerance. At the centre, two of the rocker-arm's regions on
    // either side of a loop put their vertices 0.014 apart across it, with corners of 26
    // and 175 degrees. Measured on fixed designs, mean corner deviation: bumpy-cube 16.8
    // -> 16.3, fandisk 17.1 -> 16.5, camelhead 33.3 -> 30.6, spot 29.5 -> 29.1, rocker-arm
    // 19.6 -> 17.5 (another design: 16.6 -> 17.1), ec_soapbox-A 21.2 -> 21.4.
    if (ctx.vertex_on_boundary[v] && clearance[w] >= 0.5 * boundary_clearance[r]) offer(kBoundary, w, centred);
    // A crease point nearer to the loops than a quarter of the region's inradius would
    // squeeze the vertex's patches (a crease that only clips the region near its loops
    // does not take the vertex at all). This was a test of the region's crease as a whole
    // (its farthest point), which let the vertex sit at an eighth of the inradius: the
    // rocker-arm's scan ridges took vertices at a fifth with corners of 46 to 132 degrees.
    if (on_feature[v] && clearance[w] >= 0.5 * crease_clearance[r] && clearance[w] >= 0.25 * inradius[r])
      offer(kFeature, w, centred);
    if (on_feature[v] && clearance[w] > crease_far_clearance[r]) crease_far_clearance[r] = clearance[w], crease_far[r] = w;
    if (clearance[w] >= 0.5 * inradius[r]) offer(kCentre, w, centred);
  }
  for (Index r = 0; r < nr; ++r) {
    const Region& region = ctx.regions.regions[r];
    if (region.singularities.size() != 1) continue;
    const Index sv = singularities[region.singularities[0]].vertex;
    // The refined mesh keeps the surface's vertices under their ids.
    for (const Index* t = A.topology.vertex_triangles.begin(sv); t != A.topology.vertex_triangles.end(sv); ++t) {
      const int c = corner_of(A.mesh, *t, sv);
      const Index w = ctx.wedges.of(*t, c);
      // A singularity pressed against the loops (less than half the
      // region's inradius from them) would squeeze its patches' corners;
      // the centre serves the region better then.
      if (ctx.wedge_region[w] == r && !ctx.vertex_crossing[sv]) {
        if (clearance[w] >= 0.5 * inradius[r]) best[r][kSingularity] = w;
        break;
      }
    }
  }

  std::vector<PrimalVertex> vertices(nr);
  vertex_wedge.assign(nr, kInvalid);
  for (Index r = 0; r < nr; ++r) {
    PrimalVertex& pv = vertices[r];
    pv.region = r;
    // A region that can carry its creases (crease_structure.h) takes its vertex
    // at their node, or on them: then the primal edges across its crease exits
    // run along the crease, and the crease lies on primal edges only.
    const RegionCreases& rc = ctx.regions.creases.regions[r];
    if (rc.has_crease && rc.problem == CreaseProblem::None) {
      if (rc.node != kInvalid) {
        vertex_wedge[r] = wedge_at(ctx, rc.node, r);
        pv.placement = VertexPlacement::Corner;
      } else {
        vertex_wedge[r] = best[r][kFeature] != kInvalid ? best[r][kFeature] : crease_far[r];
        pv.placement = VertexPlacement::Feature;
      }
    }
    for (Index rule = 0; rule < kRules && vertex_wedge[r] == kInvalid; ++rule) {
      if (best[r][rule] == kInvalid) continue;
      vertex_wedge[r] = best[r][rule];
      pv.placement = static_cast<VertexPlacement>(rule);
      break;
    }
    if (vertex_wedge[r] == kInvalid) {
      // A region without a vertex off its loops (a sliver between two loops
      // closer than one refined edge): take any of its wedges.
      for (Index w = 0; w < nw && vertex_wedge[r] == kInvalid; ++w)
        if (ctx.wedge_region[w] == r && !ctx.vertex_crossing[ctx.wedges.vertex[w]]) vertex_wedge[r] = w;
    }
    if (vertex_wedge[r] == kInvalid) continue;
    pv.refined_vertex = ctx.wedges.vertex[vertex_wedge[r]];
    pv.clearance = clearance[vertex_wedge[r]];
    pv.inradius = inradius[r];
    pv.position = A.mesh.positions[pv.refined_vertex];
    pv.boundary = ctx.vertex_on_boundary[pv.refined_vertex];
  }
  return vertices;
}

}  // namespace stripweave
