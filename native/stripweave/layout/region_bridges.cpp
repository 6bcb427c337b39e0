// Shortest bridges between the pieces of one region: see region_bridges.h.
#include "stripweave/layout/region_bridges.h"

#include <algorithm>
#include <limits>
#include <map>
#include <queue>
#include <tuple>
#include <unordered_map>

namespace stripweave {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Index root_of(std::vector<Index>& parent, Index v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

// The region's vertices, numbered locally, with its inner edges as adjacency.
struct RegionGraph {
  std::vector<Index> vertex;                                  // local -> refined vertex
  std::unordered_map<Index, Index> local;                     // refined vertex -> local
  std::vector<std::vector<std::pair<Index, double>>> inner;   // per local vertex
  std::vector<Index> piece;                                   // per local vertex: its piece, or kInvalid

  Index id(Index v) {
    const auto [it, fresh] = local.emplace(v, static_cast<Index>(vertex.size()));
    if (fresh) vertex.push_back(v);
    return it->second;
  }
};

RegionGraph region_graph(const LoopArrangement& A, const RegionEdges& E) {
  RegionGraph g;
  std::vector<Index> parent;
  for (Index e : E.pieces) {
    const Index a = g.id(A.topology.edges[e][0]), b = g.id(A.topology.edges[e][1]);
    while (parent.size() < g.vertex.size()) parent.push_back(static_cast<Index>(parent.size()));
    parent[root_of(parent, a)] = root_of(parent, b);
  }
  const size_t on_pieces = g.vertex.size();
  for (Index e : E.inner) g.id(A.topology.edges[e][0]), g.id(A.topology.edges[e][1]);
  g.inner.resize(g.vertex.size());
  g.piece.assign(g.vertex.size(), kInvalid);
  for (size_t v = 0; v < on_pieces; ++v) g.piece[v] = root_of(parent, static_cast<Index>(v));
  for (Index e : E.inner) {
    const Index a = g.local[A.topology.edges[e][0]], b = g.local[A.topology.edges[e][1]];
    const double w = (A.mesh.positions[g.vertex[a]] - A.mesh.positions[g.vertex[b]]).norm();
    g.inner[a].push_back({b, w});
    g.inner[b].push_back({a, w});
  }
  return g;
}

// Per local vertex: the distance to the nearest piece, that piece's label
// and the vertex before it on the way there (one Dijkstra from all pieces).
struct NearestPiece {
  std::vector<double> d;
  std::vector<Index> label, pred;
};

NearestPiece nearest_pieces(const RegionGraph& g) {
  const size_t n = g.vertex.size();
  NearestPiece p{std::vector<double>(n, kInf), std::vector<Index>(n, kInvalid), std::vector<Index>(n, kInvalid)};
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (size_t v = 0; v < n; ++v)
    if (g.piece[v] != kInvalid) p.d[v] = 0, p.label[v] = g.piece[v], queue.push({0.0, static_cast<Index>(v)});
  while (!queue.empty()) {
    const auto [dv, v] = queue.top();
    queue.pop();
    if (dv > p.d[v]) continue;
    for (const auto& [w, len] : g.inner[v])
      if (dv + len < p.d[w]) p.d[w] = dv + len, p.label[w] = p.label[v], p.pred[w] = v, queue.push({p.d[w], w});
  }
  return p;
}

}  // namespace

std::vector<Bridge> shortest_bridges(const LoopArrangement& A, const RegionEdges& edges) {
  const RegionGraph g = region_graph(A, edges);
  const NearestPiece p = nearest_pieces(g);
  // Per pair of pieces, the inner edge that closes the shortest bridge.
  std::map<std::pair<Index, Index>, std::tuple<double, Index, Index>> best;   // pieces -> (length, ends)
  for (size_t v = 0; v < g.vertex.size(); ++v)
    for (const auto& [w, len] : g.inner[v]) {
      if (p.label[v] == kInvalid || p.label[w] == kInvalid || p.label[v] >= p.label[w]) continue;
      const double length = p.d[v] + len + p.d[w];
      const auto key = std::make_pair(p.label[v], p.label[w]);
      const auto it = best.find(key);
      if (it == best.end() || length < std::get<0>(it->second))
        best[key] = {length, static_cast<Index>(v), w};
    }
  std::vector<Bridge> out;
  for (const auto& [pieces, found] : best) {
    const auto& [length, v, w] = found;
    Bridge b{length, {}};
    for (Index x = v; x != kInvalid; x = p.pred[x]) b.path.push_back(g.vertex[x]);
    std::reverse(b.path.begin(), b.path.end());
    for (Index x = w; x != kInvalid; x = p.pred[x]) b.path.push_back(g.vertex[x]);
    out.push_back(std::move(b));
  }
  std::stable_sort(out.begin(), out.end(), [](const Bridge& a, const Bridge& b) { return a.length < b.length; });
  return out;
}

}  // namespace stripweave
