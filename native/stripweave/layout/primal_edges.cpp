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

}  // namespace

std::vector<PrimalEdge> route_primal_edges(const PrimalContext& ctx, const std::vector<Index>& vertex_wedge,
                                           std::vector<std::string>& problems) {
  const LoopArrangement& A = ctx.arrangement;
  const TriangleMesh& m = A.mesh;
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

  // Untangle. The guesses of one region lie in one shortest-path tree, so
  // they never cross, but two of them may share a first stretch, and an
  // edge may run along a loop or the boundary where its neighbour across
  // runs too. Mesh-edge paths can only meet at a shared vertex, so: going
  // through the arcs from the least cheap per unit length (edges across
  // open surface) to the cheapest (edges on creases and the boundary, which
  // keep their route), an edge whose inner vertices another edge also uses
  // is routed again with every other edge's inner vertices blocked. The
  // re-route is a shortest path from the left vertex to the right one over
  // the two regions' wedges in two layers, the only way from layer 0 to
  // layer 1 being across this arc (once, also when both sides are one
  // region, as on a torus). If no route is left, the guess stays, and the
  // overlap is reported.
  std::vector<Index> order(na);
  for (Index k = 0; k < na; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return cheapness[a] > cheapness[b]; });
  std::vector<Index> use(m.num_vertices(), 0);  // inner vertices of the current routes
  std::vector<std::vector<Index>> routed = guess;
  std::vector<Index> routed_crossing = guess_crossing;
  auto count = [&](const std::vector<Index>& path, Index delta) {
    for (size_t i = 1; i + 1 < path.size(); ++i) use[path[i]] += delta;
  };
  for (Index k = 0; k < na; ++k) count(routed[k], +1);
  const Index nw = ctx.wedges.count();
  std::vector<double> d2(2 * static_cast<size_t>(nw), inf);
  std::vector<Index> p2(2 * static_cast<size_t>(nw), kInvalid);
  std::vector<Index> touched;
  for (Index k : order) {
    if (guess[k].empty() || pinned[k]) continue;
    bool shared = false;
    for (size_t i = 1; i + 1 < routed[k].size() && !shared; ++i) shared = use[routed[k][i]] > 1;
    // Its end vertices may not be passed through by others either.
    for (Index v : {routed[k].front(), routed[k].back()}) shared |= use[v] > 0;
    if (!shared) continue;
    count(routed[k], -1);
    auto used = [&](Index v) { return use[v] > 0; };
    const LoopArc& arc = A.arcs[k];
    const Index L = ctx.regions.arc_left[k], R = ctx.regions.arc_right[k];
    std::vector<std::pair<Index, Index>> links;  // (from wedge in layer 0, to wedge in layer 1)
    for (size_t i = 0; i < arc.vertices.size(); ++i) {
      if (ctx.vertex_crossing[arc.vertices[i]] || used(arc.vertices[i])) continue;
      const auto [wl, wr] = sides(arc, i);
      if (wl == kInvalid || wr == kInvalid) continue;
      links.push_back({wl, wr});
      links.push_back({wr, wl});
    }
    std::sort(links.begin(), links.end());
    const Index source = vertex_wedge[L], target = nw + vertex_wedge[R];
    for (Index x : touched) d2[x] = inf, p2[x] = kInvalid;
    touched.clear();
    using Item = std::pair<double, Index>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    d2[source] = 0, touched.push_back(source), heap.push({0.0, source});
    auto relax = [&](Index from, Index to, double nd) {
      if (nd >= d2[to]) return;
      if (d2[to] == inf) touched.push_back(to);
      d2[to] = nd, p2[to] = from;
      heap.push({nd, to});
    };
    while (!heap.empty()) {
      const auto [d, x] = heap.top();
      heap.pop();
      if (d > d2[x]) continue;
      if (x == target) break;
      const Index layer = x >= nw, w = x - layer * nw;
      if (x != source && used(ctx.wedges.vertex[w])) continue;  // reached, but not passed through
      for (Index j = ctx.wedge_neighbours.offsets[w]; j < ctx.wedge_neighbours.offsets[w + 1]; ++j) {
        const Index y = ctx.wedge_neighbours.indices[j];
        const Index r = ctx.wedge_region[y];
        if ((r != L && r != R) || blocked(y)) continue;
        const Index yv = ctx.wedges.vertex[y];
        if (used(yv) && y + layer * nw != target) continue;
        relax(x, y + layer * nw, d + cost(ctx.wedge_neighbour_edge.indices[j]));
      }
      if (layer == 0) {
        auto it = std::lower_bound(links.begin(), links.end(), std::pair<Index, Index>(w, kInvalid));
        for (; it != links.end() && it->first == w; ++it) relax(x, nw + it->second, d);
      }
    }
    if (d2[target] == inf) {
      problems.push_back("arc " + std::to_string(k) + " (loop " + std::to_string(arc.loop) +
                         "): the other primal edges leave no free corridor; its edge overlaps them");
      count(routed[k], +1);
      continue;
    }
    std::vector<Index> path;
    Index crossing_at = 0;
    for (Index x = target; x != kInvalid; x = p2[x]) {
      const Index w = x >= nw ? x - nw : x;
      // The crossing link joins two wedges of one vertex: keep it once.
      if (!path.empty() && path.back() == ctx.wedges.vertex[w]) {
        crossing_at = static_cast<Index>(path.size()) - 1;
        continue;
      }
      path.push_back(ctx.wedges.vertex[w]);
    }
    std::reverse(path.begin(), path.end());
    crossing_at = static_cast<Index>(path.size()) - 1 - crossing_at;
    routed[k] = std::move(path);
    routed_crossing[k] = crossing_at;
    count(routed[k], +1);
  }

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
