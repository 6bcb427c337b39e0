// Primal edges: one per arc, routed through the corridor of the two regions
// the arc separates (paper §7; rules in quad_layout.h).
//
// Every region grows one shortest-path tree from its vertex over the wedges
// of the cut-open surface. A primal edge is the tree path from the left
// region's vertex to a point x of the arc, then across the arc (x's wedge on
// the other side is the same point), then the right tree's path to the
// right vertex; x minimizes the sum of the two distances, so the edge is the
// shortest corridor path that crosses its arc exactly once. Because each
// half lies in one tree, two edges leaving the same vertex never cross (at
// worst they share a first stretch, which cut_primal_patches reports), and
// edges in different regions meet only at their own arc.
//
// An edge across an arc that a crease crosses is the crease chain through
// the exit (crease_route), and keeps that route: so the crease network lies
// on primal edges wherever the regions can carry it (issue 17).
//
// An edge the user routed by hand (EdgeRoute, primal_edge_routes.cpp) is the
// cheapest corridor path through the user's point (Untangler::route_through),
// routed before the others are untangled and kept, as a crease route is.
//
// Costs: a refined edge costs its length, times kCheap on a sharp feature
// or the open boundary (a primal edge whose corridor holds a crease follows
// it, and edges of boundary regions run along the boundary between boundary
// vertices), times kOnLoop along a loop (an edge running along its arc on
// one side, and its neighbour's on the other, would coincide). Paths never
// pass through a loop crossing, which would pinch its patch.
#include "stripweave/layout/primalization.h"

#include <algorithm>
#include <limits>
#include <queue>

namespace stripweave {

namespace {

constexpr double kCheap = 0.4;
constexpr double kOnLoop = 4.0;

// The primal edge across arc k when a crease crosses it (crease_structure.h):
// on each side, the crease path from the exit to the region's vertex, or the
// shortest-path tree's path (`trace`, from a wedge back to its vertex) on a
// side the crease does not enter. False (and no route) unless the exit is a
// single point, both regions have vertices, and every side the crease enters
// carries it to its vertex.
template <class Trace>
bool crease_route(const PrimalContext& ctx, const std::vector<Index>& vertex_wedge, Index k, const Trace& trace,
                  std::vector<Index>& path, Index& crossing_at) {
  const LoopArrangement& A = ctx.arrangement;
  const Index x = ctx.regions.creases.arc_exit[k];
  const Index L = ctx.regions.arc_left[k], R = ctx.regions.arc_right[k];
  if (x == kInvalid || L == kInvalid || R == kInvalid) return false;
  if (vertex_wedge[L] == kInvalid || vertex_wedge[R] == kInvalid) return false;
  const LoopArc& arc = A.arcs[k];
  const auto at = std::find(arc.vertices.begin(), arc.vertices.end(), x);
  if (at == arc.vertices.end()) return false;
  const auto [wl, wr] = ctx.arc_side_wedges(k, static_cast<size_t>(at - arc.vertices.begin()));
  if (wl == kInvalid || wr == kInvalid) return false;
  // The crease enters region r at x when one of its edges at x lies in r.
  auto enters = [&](Index r) {
    const MeshTopology& rt = A.topology;
    for (const Index* n = rt.vertex_neighbours.begin(x); n != rt.vertex_neighbours.end(x); ++n) {
      const Index e = rt.find_edge(x, *n);
      if (ctx.edge_feature[e] && !A.on_loop(e) && ctx.regions.triangle_region[rt.edge_triangles[e][0]] == r)
        return true;
    }
    return false;
  };
  auto half = [&](Index r, Index w) {  // from the region's vertex to x
    const Index v = ctx.wedges.vertex[vertex_wedge[r]];
    if (enters(r)) return crease_path_in_region(ctx, r, v, x);
    std::vector<Index> p = trace(w);
    std::reverse(p.begin(), p.end());
    return p;
  };
  std::vector<Index> left = half(L, wl), right = half(R, wr);
  if (left.empty() || right.empty() || left.back() != x || right.back() != x) return false;
  path = std::move(left);
  crossing_at = static_cast<Index>(path.size()) - 1;
  path.insert(path.end(), right.rbegin() + 1, right.rend());
  return true;
}

// Untangling. The first guesses of one region lie in one shortest-path
// tree, so they never cross, but two of them may share a first stretch, and
// an edge may run along a loop or the boundary where its neighbour across
// runs too. Mesh-edge paths can only meet at a shared vertex, so an edge
// whose inner vertices another edge also uses (or that passes through
// another's end) is routed again with every other edge's inner vertices
// blocked: a shortest path from the left vertex to the right one over the
// two regions' wedges in two layers, the only way from layer 0 to layer 1
// being across its arc (once, also when both sides are one region, as on a
// torus). Edges on crease exits keep their routes (pinned).
//
// Routed one after another, an edge can find its corridor closed by edges
// routed before it that had room elsewhere: the order decides, not the
// geometry. So an edge left without a route is ripped up and rerouted: its
// cheapest route through as few vertices of other unpinned edges as
// possible (each costs kConflict, far more than any path), then those edges
// are routed again around everything else. All or nothing: if one of them
// finds no route, every edge keeps its former route. Each success leaves
// fewer shared edges, so the rounds end.
constexpr int kRipUpRounds = 3;
constexpr double kConflict = 1e3;  // normalized units: a path is a few units at most

class Untangler {
 public:
  std::vector<std::vector<Index>> routed;  // per arc, its edge's refined vertices
  std::vector<Index> crossing;             // per arc, where in routed[k] the edge crosses the arc

  // edge_cost: per refined edge, what a route pays to run along it.
  Untangler(const PrimalContext& ctx, const std::vector<Index>& vertex_wedge, std::vector<double> edge_cost,
            std::vector<std::vector<Index>> routes, std::vector<Index> crossings, std::vector<std::uint8_t> pinned)
      : routed(std::move(routes)), crossing(std::move(crossings)), ctx_(ctx), vertex_wedge_(vertex_wedge),
        edge_cost_(std::move(edge_cost)), pinned_(std::move(pinned)),
        use_(ctx.arrangement.mesh.num_vertices(), 0), pinned_use_(use_.size(), 0), nw_(ctx.wedges.count()),
        dist_(2 * static_cast<size_t>(nw_), kInf), pred_(dist_.size(), kInvalid) {
    for (Index k = 0; k < static_cast<Index>(routed.size()); ++k) {
      count(k, +1);
      if (pinned_[k]) for_inner(k, [&](Index v) { ++pinned_use_[v]; });
    }
  }

  // Does an unpinned edge share a vertex with another (inner vertices, or
  // another edge passing through one of its ends)?
  bool shared(Index k) const {
    const std::vector<Index>& p = routed[k];
    if (p.empty() || pinned_[k]) return false;
    for (size_t i = 1; i + 1 < p.size(); ++i)
      if (use_[p[i]] > 1) return true;
    return use_[p.front()] > 0 || use_[p.back()] > 0;
  }

  // Route k again around every other edge; false (and its route kept) if none is left.
  bool reroute(Index k) {
    count(k, -1);
    std::vector<Index> path;
    Index at = 0;
    const bool found = search(k, [&](Index v) { return use_[v] > 0 ? kInf : 0.0; }, path, at);
    if (found) routed[k] = std::move(path), crossing[k] = at;
    count(k, +1);
    return found;
  }

  // Route k by hand through wedge `through` of one of its regions (an
  // EdgeRoute): the cheapest path from its left vertex to the point, then on
  // to its right vertex, crossing the arc once on the way, around the routes
  // already pinned, the second leg never re-entering the first (no spur).
  // The route is pinned from then on. False (and its route kept) if the
  // pinned routes leave no such path.
  bool pinned(Index k) const { return pinned_[k] != 0; }

  bool route_through(Index k, Index through) {
    const Index L = ctx_.regions.arc_left[k], R = ctx_.regions.arc_right[k];
    const Index r = ctx_.wedge_region[through];
    const Index source = vertex_wedge_[L], target = nw_ + vertex_wedge_[R];
    const auto free = [&](Index v) { return pinned_use_[v] > 0 ? kInf : 0.0; };
    std::vector<Index> best;
    Index best_at = 0;
    double best_cost = kInf;
    // The point in the left region is reached before the arc (layer 0), in
    // the right one after it; in both when the arc has one region on both sides.
    for (Index layer = 0; layer < 2; ++layer) {
      if (r != (layer == 0 ? L : R)) continue;
      const Index via = through + layer * nw_;
      std::vector<Index> first, second;
      Index first_at = 0, second_at = 0;
      if (!search(k, source, via, free, first, first_at)) continue;
      const double first_cost = dist_[via];
      std::vector<std::uint8_t> taken(use_.size(), 0);
      for (size_t i = 0; i + 1 < first.size(); ++i) taken[first[i]] = 1;
      const auto fresh = [&](Index v) { return taken[v] ? kInf : free(v); };
      if (!search(k, via, target, fresh, second, second_at)) continue;
      if (first_cost + dist_[target] >= best_cost) continue;
      best_cost = first_cost + dist_[target];
      best = first;
      best.insert(best.end(), second.begin() + 1, second.end());
      best_at = layer == 0 ? static_cast<Index>(first.size()) - 1 + second_at : first_at;
    }
    if (best.empty()) return false;
    count(k, -1);
    routed[k] = std::move(best), crossing[k] = best_at;
    count(k, +1);
    if (!pinned_[k]) for_inner(k, [&](Index v) { ++pinned_use_[v]; });
    pinned_[k] = 1;
    return true;
  }

  bool rip_up_and_reroute(Index k) {
    count(k, -1);
    std::vector<Index> path;
    Index at = 0;
    const auto conflict = [&](Index v) { return pinned_use_[v] > 0 ? kInf : use_[v] > 0 ? kConflict : 0.0; };
    if (!search(k, conflict, path, at)) {
      count(k, +1);
      return false;
    }
    // The victims leave the mesh together; each comes back (reroute) around
    // k and the victims rerouted before it.
    const std::vector<Index> victims = passing_through(path, k);
    std::vector<std::pair<std::vector<Index>, Index>> before{{routed[k], crossing[k]}};
    for (Index j : victims) before.push_back({routed[j], crossing[j]}), count(j, -1);
    routed[k] = std::move(path), crossing[k] = at;
    count(k, +1);
    size_t done = 0;
    for (; done < victims.size(); ++done) {
      count(victims[done], +1);  // reroute takes it out again
      if (!reroute(victims[done])) break;
    }
    if (done == victims.size()) return true;
    // Undo: every route as before (the victims past the failed one are out).
    set_route(k, before[0]);
    for (size_t h = 0; h < victims.size(); ++h) {
      if (h > done) count(victims[h], +1);
      set_route(victims[h], before[h + 1]);
    }
    return false;
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  const PrimalContext& ctx_;
  const std::vector<Index>& vertex_wedge_;
  std::vector<double> edge_cost_;  // per refined edge
  std::vector<std::uint8_t> pinned_;
  std::vector<Index> use_;         // per refined vertex: the edges whose inner vertex it is
  std::vector<Index> pinned_use_;  // ... of them pinned
  Index nw_;
  std::vector<double> dist_;  // per wedge in two layers
  std::vector<Index> pred_;
  std::vector<Index> touched_;

  template <class F>
  void for_inner(Index k, F f) const {
    for (size_t i = 1; i + 1 < routed[k].size(); ++i) f(routed[k][i]);
  }
  void count(Index k, Index delta) {
    for_inner(k, [&](Index v) { use_[v] += delta; });
  }
  // Put counted edge k on `route` (a path and where it crosses its arc).
  void set_route(Index k, const std::pair<std::vector<Index>, Index>& route) {
    count(k, -1);
    routed[k] = route.first, crossing[k] = route.second;
    count(k, +1);
  }

  // The unpinned edges other than k with an inner vertex on `path`, in arc order.
  std::vector<Index> passing_through(const std::vector<Index>& path, Index k) const {
    std::vector<std::uint8_t> on(use_.size(), 0);
    for (Index v : path) on[v] = 1;
    std::vector<Index> out;
    for (Index j = 0; j < static_cast<Index>(routed.size()); ++j) {
      if (j == k || pinned_[j]) continue;
      bool hit = false;
      for_inner(j, [&](Index v) { hit |= on[v] != 0; });
      if (hit) out.push_back(j);
    }
    return out;
  }

  // The cheapest route of arc k's edge: edge costs plus penalty(v) for each
  // refined vertex it enters (its target excepted; infinity: never entered),
  // crossing the arc once and never entering a loop crossing.
  template <class Penalty>
  bool search(Index k, const Penalty& penalty, std::vector<Index>& path, Index& crossing_at) {
    const Index L = ctx_.regions.arc_left[k], R = ctx_.regions.arc_right[k];
    return search(k, vertex_wedge_[L], nw_ + vertex_wedge_[R], penalty, path, crossing_at);
  }

  // The same between two layered wedges (layer 1: past the arc): source and
  // target in one layer give a path that does not cross the arc.
  template <class Penalty>
  bool search(Index k, Index source, Index target, const Penalty& penalty, std::vector<Index>& path,
              Index& crossing_at) {
    const LoopArc& arc = ctx_.arrangement.arcs[k];
    const Index L = ctx_.regions.arc_left[k], R = ctx_.regions.arc_right[k];
    std::vector<std::pair<Index, Index>> links;  // (from wedge in layer 0, to wedge in layer 1)
    for (size_t i = 0; i < arc.vertices.size(); ++i) {
      if (ctx_.vertex_crossing[arc.vertices[i]] || !(penalty(arc.vertices[i]) < kInf)) continue;
      const auto [wl, wr] = ctx_.arc_side_wedges(k, i);
      if (wl == kInvalid || wr == kInvalid) continue;
      links.push_back({wl, wr});
      links.push_back({wr, wl});
    }
    std::sort(links.begin(), links.end());
    for (Index x : touched_) dist_[x] = kInf, pred_[x] = kInvalid;
    touched_.clear();
    using Item = std::pair<double, Index>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    dist_[source] = 0, touched_.push_back(source), heap.push({0.0, source});
    auto relax = [&](Index from, Index to, double nd) {
      if (nd >= dist_[to]) return;
      if (dist_[to] == kInf) touched_.push_back(to);
      dist_[to] = nd, pred_[to] = from;
      heap.push({nd, to});
    };
    while (!heap.empty()) {
      const auto [d, x] = heap.top();
      heap.pop();
      if (d > dist_[x]) continue;
      if (x == target) break;
      const Index layer = x >= nw_, w = x - layer * nw_;
      for (Index j = ctx_.wedge_neighbours.offsets[w]; j < ctx_.wedge_neighbours.offsets[w + 1]; ++j) {
        const Index y = ctx_.wedge_neighbours.indices[j];
        const Index r = ctx_.wedge_region[y];
        if ((r != L && r != R) || ctx_.vertex_crossing[ctx_.wedges.vertex[y]]) continue;
        const double extra = y + layer * nw_ == target ? 0.0 : penalty(ctx_.wedges.vertex[y]);
        if (!(extra < kInf)) continue;  // never entered, so never passed through
        relax(x, y + layer * nw_, d + edge_cost_[ctx_.wedge_neighbour_edge.indices[j]] + extra);
      }
      if (layer == 0) {  // across the arc at a vertex already entered
        auto it = std::lower_bound(links.begin(), links.end(), std::pair<Index, Index>(w, kInvalid));
        for (; it != links.end() && it->first == w; ++it) relax(x, nw_ + it->second, d);
      }
    }
    if (dist_[target] == kInf) return false;
    read_route(target, path, crossing_at);
    return true;
  }

  void read_route(Index target, std::vector<Index>& path, Index& crossing_at) const {
    path.clear();
    crossing_at = 0;
    for (Index x = target; x != kInvalid; x = pred_[x]) {
      const Index w = x >= nw_ ? x - nw_ : x;
      // The crossing link joins two wedges of one vertex: keep it once.
      if (!path.empty() && path.back() == ctx_.wedges.vertex[w]) {
        crossing_at = static_cast<Index>(path.size()) - 1;
        continue;
      }
      path.push_back(ctx_.wedges.vertex[w]);
    }
    std::reverse(path.begin(), path.end());
    crossing_at = static_cast<Index>(path.size()) - 1 - crossing_at;
  }
};

}  // namespace

std::vector<PrimalEdge> route_primal_edges(const PrimalContext& ctx, const std::vector<Index>& vertex_wedge,
                                           const std::vector<ResolvedEdgeRoute>& routes,
                                           std::vector<std::string>& problems) {
  const LoopArrangement& A = ctx.arrangement;
  const MeshTopology& rt = A.topology;

  auto cost = [&](Index e) {
    double c = ctx.edge_length[e];
    if (ctx.edge_feature[e] || rt.is_boundary_edge(e)) c *= kCheap;
    if (A.on_loop(e)) c *= kOnLoop;
    return c;
  };
  auto blocked = [&](Index w) { return ctx.vertex_crossing[ctx.wedges.vertex[w]] != 0; };
  std::vector<Index> pred;
  const std::vector<double> dist = ctx.shortest_paths(vertex_wedge, cost, blocked, &pred);

  auto sides = [&](const LoopArc& arc, size_t i) { return ctx.arc_side_wedges(&arc - A.arcs.data(), i); };
  auto trace = [&](Index w) {
    std::vector<Index> path;
    for (; w != kInvalid; w = pred[w]) path.push_back(ctx.wedges.vertex[w]);
    return path;  // from w back to its tree's root
  };

  // First guess per arc: the two trees' paths (crossing where their
  // distances sum to the least), and how cheap per unit length it is.
  const double inf = std::numeric_limits<double>::infinity();
  const Index na = static_cast<Index>(A.arcs.size());
  std::vector<std::vector<Index>> guess(na);
  std::vector<Index> guess_crossing(na, 0);
  std::vector<double> cheapness(na, inf);
  for (Index k = 0; k < na; ++k) {
    const LoopArc& arc = A.arcs[k];
    if (ctx.regions.arc_left[k] == kInvalid || ctx.regions.arc_right[k] == kInvalid) continue;
    double best = inf;
    std::pair<Index, Index> at{kInvalid, kInvalid};
    for (size_t i = 0; i < arc.vertices.size(); ++i) {
      if (ctx.vertex_crossing[arc.vertices[i]]) continue;
      const auto [wl, wr] = sides(arc, i);
      if (wl == kInvalid || wr == kInvalid) continue;
      const double d = dist[wl] + dist[wr];
      if (d < best) best = d, at = {wl, wr};
    }
    if (best == inf) continue;
    std::vector<Index> left = trace(at.first), right = trace(at.second);
    std::reverse(left.begin(), left.end());
    guess_crossing[k] = static_cast<Index>(left.size()) - 1;
    guess[k] = left;
    guess[k].insert(guess[k].end(), right.begin() + 1, right.end());  // x once
    double length = 0;
    for (size_t i = 0; i + 1 < guess[k].size(); ++i) length += ctx.edge_length[rt.find_edge(guess[k][i], guess[k][i + 1])];
    cheapness[k] = length > 0 ? best / length : 1.0;
  }

  // Edges across crease exits follow the crease and keep their route.
  std::vector<std::uint8_t> pinned(na, 0);
  for (Index k = 0; k < na; ++k) {
    std::vector<Index> path;
    Index crossing_at = 0;
    if (!crease_route(ctx, vertex_wedge, k, trace, path, crossing_at)) continue;
    guess[k] = std::move(path);
    guess_crossing[k] = crossing_at;
    cheapness[k] = 0;
    pinned[k] = 1;
  }

  // Untangle (Untangler, above): edges across open surface first (the least
  // cheap per unit length), then those on creases and the boundary.
  std::vector<Index> order(na);
  for (Index k = 0; k < na; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return cheapness[a] > cheapness[b]; });
  std::vector<double> edge_cost(rt.num_edges());
  for (Index e = 0; e < rt.num_edges(); ++e) edge_cost[e] = cost(e);
  Untangler u(ctx, vertex_wedge, std::move(edge_cost), std::move(guess), std::move(guess_crossing), std::move(pinned));
  // Edges routed by hand go first and keep their routes, as crease routes
  // do; an edge on a crease exit keeps the crease (the crease must lie on
  // primal edges), as a pin leaves a part's corner where it is.
  std::vector<Index> through(na, kInvalid), route_of(na, kInvalid);
  for (const ResolvedEdgeRoute& r : routes) {
    route_of[r.arc] = r.route;
    const std::string which = "edge route " + std::to_string(r.route + 1) + " (arc " + std::to_string(r.arc) + ")";
    if (u.pinned(r.arc))
      problems.push_back(which + ": the edge follows a crease and keeps its route");
    else if (u.route_through(r.arc, r.wedge))
      through[r.arc] = ctx.wedges.vertex[r.wedge];
    else
      problems.push_back(which + ": the routes pinned before it leave no corridor path through the point");
  }
  std::vector<Index> stuck;
  for (Index k : order)
    if (u.shared(k) && !u.reroute(k)) stuck.push_back(k);
  for (int round = 0; round < kRipUpRounds && !stuck.empty(); ++round) {
    std::vector<Index> still;
    for (Index k : stuck)
      if (u.shared(k) && !u.rip_up_and_reroute(k)) still.push_back(k);
    if (still.size() == stuck.size()) break;
    stuck.swap(still);
  }
  for (Index k : stuck)
    if (u.shared(k))
      problems.push_back("arc " + std::to_string(k) + " (loop " + std::to_string(A.arcs[k].loop) +
                         "): the other primal edges leave no free corridor; its edge overlaps them");
  std::vector<std::vector<Index>> routed = std::move(u.routed);
  std::vector<Index> routed_crossing = std::move(u.crossing);

  std::vector<PrimalEdge> edges;
  for (Index k = 0; k < na; ++k) {
    PrimalEdge edge;
    edge.arc = k;
    edge.v0 = ctx.regions.arc_left[k];
    edge.v1 = ctx.regions.arc_right[k];
    if (routed[k].empty()) {
      problems.push_back("arc " + std::to_string(k) + " (loop " + std::to_string(A.arcs[k].loop) +
                         "): no corridor path joins its two regions' vertices");
      continue;
    }
    edge.path = std::move(routed[k]);
    edge.crossing = routed_crossing[k];
    edge.through = through[k];
    edge.route = route_of[k];
    double sharp = 0, boundary = 0;
    for (size_t i = 0; i + 1 < edge.path.size(); ++i) {
      const Index e = rt.find_edge(edge.path[i], edge.path[i + 1]);
      const double len = ctx.edge_length[e];
      edge.length += len;
      sharp += ctx.edge_feature[e] ? len : 0;
      boundary += rt.is_boundary_edge(e) ? len : 0;
    }
    // "Most of its length": the ends may step off a crease to reach a vertex.
    edge.sharp = sharp > 0.9 * edge.length;
    edge.boundary = boundary > 0.9 * edge.length;
    edges.push_back(std::move(edge));
  }
  return edges;
}

}  // namespace stripweave
