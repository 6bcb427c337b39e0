#include "stripweave/elastica/shortest_paths.h"

#include "stripweave/elastica/radix_heap.h"

#include <algorithm>

namespace stripweave {

namespace {

using MinHeap = RadixHeap<Index>;

constexpr std::size_t kCancelPollMask = 4095;  // check cancellation every 4096 pops

// The midpoint of a node's g-edge, for the A* heuristic.
Vec3 midpoint(const SearchContext& ctx, Index n) {
  return 0.5 * (ctx.surface.mesh.positions[ctx.graph.tail[n]] + ctx.surface.mesh.positions[ctx.graph.head[n]]);
}

std::vector<Index> trace_back(const SearchWorkspace& ws, Index from, Index source, Index last_pred) {
  // `last_pred` is the predecessor of `from` on this path (for re-entry into
  // the source, whose own pred is the start marker).
  std::vector<Index> chain{from};
  Index n = last_pred;
  while (n != kInvalid) {
    chain.push_back(n);
    if (n == source) break;
    n = ws.pred(n);
  }
  std::reverse(chain.begin(), chain.end());
  return chain;
}

}  // namespace

std::size_t SearchWorkspaces::memory_bytes() const {
  std::size_t bytes = forward.memory_bytes() + backward.memory_bytes();
  for (const SearchWorkspace& w : layers) bytes += w.memory_bytes();
  return bytes;
}

void SearchWorkspaces::release() {
  forward.release();
  backward.release();
  std::vector<SearchWorkspace>().swap(layers);
}

void SearchWorkspace::prepare(Index nodes) {
  if (static_cast<Index>(slot_.size()) != nodes) {
    slot_.assign(nodes, Slot{kUnreachable, 0, 0});
    pred_.assign(nodes, kInvalid);
    epoch_ = 0;
  }
  if (++epoch_ == 0) {  // wrapped: forget every old stamp
    for (Slot& s : slot_) s.stamp = s.settled = 0;
    epoch_ = 1;
  }
  settled = 0;
}

double chain_cost(const ElasticaGraph& g, const std::vector<Index>& nodes) {
  double cost = 0;
  for (size_t i = 0; i + 1 < nodes.size(); ++i) {
    const Index from = nodes[i], to = nodes[i + 1];
    bool joined = false;
    for (Index a = g.arc_offsets[from]; a < g.arc_offsets[from + 1]; ++a)
      if (g.arc_head[a] == to) {
        cost += g.arc_weight[a];
        joined = true;
        break;
      }
    if (!joined) return kUnreachable;
  }
  return cost;
}

std::vector<Index> reversed_chain(const ElasticaGraph& g, const std::vector<Index>& nodes) {
  std::vector<Index> r(nodes.rbegin(), nodes.rend());
  for (Index& n : r) n = g.reverse[n];
  return r;
}

// Unidirectional search (Dijkstra, or A* toward `target` when guided).
// Re-entering the source is recorded as the loop through it.
static Path search_one(const SearchContext& ctx, SearchWorkspace& ws, Index source, Index target, bool guided,
                       double bound, std::size_t budget) {
  const ElasticaGraph& g = ctx.graph;
  ws.prepare(g.num_nodes());
  const Vec3 goal = midpoint(ctx, target);
  auto h = [&](Index n) { return guided ? kHeuristicScale * (midpoint(ctx, n) - goal).norm() : 0.0; };
  MinHeap heap;
  ws.set(source, 0.0, kInvalid);
  heap.push(h(source), source);
  Path best;
  Index best_pred = kInvalid;
  while (!heap.empty()) {
    const auto [key, n] = heap.pop();
    if (!ws.settle(n)) continue;  // stale entry
    const double d = ws.dist(n);
    if (key >= std::min(best.cost, bound)) break;
    if (n == target && n != source) {
      best.cost = d;
      best.nodes = trace_back(ws, n, source, ws.pred(n));
      return best;
    }
    if ((++ws.settled & kCancelPollMask) == 0 && ctx.check_cancel) ctx.check_cancel();
    if (ws.settled > budget) {
      Path aborted;
      aborted.aborted = true;
      return aborted;
    }
    for (Index a = g.arc_offsets[n]; a < g.arc_offsets[n + 1]; ++a) {
      const Index m = g.arc_head[a];
      if (ctx.is_disabled(m)) continue;
      const double dm = d + g.arc_weight[a];
      if (m == source) {  // a loop closes
        if (source == target && dm < best.cost) best.cost = dm, best_pred = n;
        continue;
      }
      if (dm < ws.dist(m)) {
        ws.set(m, dm, n);
        heap.push(dm + h(m), m);
      }
    }
  }
  if (source == target && best.cost < bound) best.nodes = trace_back(ws, source, source, best_pred);
  else best.cost = kUnreachable;
  return best;
}

// Bidirectional search: forward from the source, and forward from
// reverse(target), which by the symmetry of the weights is the backward search
// from the target. A meeting at node X joins source..X with reverse(...).
static Path search_two(const SearchContext& ctx, SearchWorkspace& fw, SearchWorkspace& bw, Index source,
                       Index target, double bound, std::size_t budget) {
  const ElasticaGraph& g = ctx.graph;
  fw.prepare(g.num_nodes());
  bw.prepare(g.num_nodes());
  const Index back_source = g.reverse[target];
  MinHeap hf, hb;
  fw.set(source, 0.0, kInvalid);
  bw.set(back_source, 0.0, kInvalid);
  hf.push(0.0, source);
  hb.push(0.0, back_source);
  double mu = bound;
  Index meet = kInvalid, meet_pred = kInvalid;
  bool meet_forward = true;
  // A meeting relaxes `from -> m` in one search while the other has reached
  // reverse(m). The trivial meeting (source itself, no arc) never happens:
  // meetings are only checked on relaxation.
  auto expand = [&](SearchWorkspace& self, SearchWorkspace& other, MinHeap& heap, bool forward) {
    const Index n = heap.pop().second;
    if (!self.settle(n)) return;
    const double key = self.dist(n);
    if ((++self.settled & kCancelPollMask) == 0 && ctx.check_cancel) ctx.check_cancel();
    for (Index a = g.arc_offsets[n]; a < g.arc_offsets[n + 1]; ++a) {
      const Index m = g.arc_head[a];
      // The backward search's node m stands for reverse(m) on the path: that
      // is the node a mask must keep out (checking m itself was right only for
      // masks closed under reverse; an asymmetric one let disabled nodes in).
      if (ctx.is_disabled(forward ? m : g.reverse[m])) continue;
      const double dm = key + g.arc_weight[a];
      const double dr = other.dist(g.reverse[m]);
      if (dr < kUnreachable && dm + dr < mu) {
        mu = dm + dr;
        meet = m, meet_pred = n, meet_forward = forward;
      }
      if (dm < self.dist(m) && !(forward ? m == source : m == back_source)) {
        self.set(m, dm, n);
        heap.push(dm, m);
      }
    }
  };
  while (!hf.empty() && !hb.empty()) {
    if (fw.settled + bw.settled > budget) {
      Path aborted;
      aborted.aborted = true;
      return aborted;
    }
    const double top_f = hf.top_key(), top_b = hb.top_key();
    if (top_f + top_b >= mu) break;
    // Pohl's cardinality rule: grow the side with the smaller queue. The
    // stopping test above holds whichever side grows, so the path is the
    // same; but where one side runs into costly ground (a crease crossed at
    // a slant) its few cheap states are used up at once and its key jumps,
    // and alternating by key then made the other side sweep a whole flat
    // face up to mu minus that jump. Growing the thin side instead raises
    // its key cheaply (handle.step: a third fewer settled nodes per start).
    if (hf.size() <= hb.size())
      expand(fw, bw, hf, true);
    else
      expand(bw, fw, hb, false);
  }
  Path path;
  if (meet == kInvalid) return path;
  // Half paths: the search that made the meeting ends at meet (via meet_pred);
  // the other search reached reverse(meet).
  SearchWorkspace& self = meet_forward ? fw : bw;
  SearchWorkspace& other = meet_forward ? bw : fw;
  const Index self_source = meet_forward ? source : back_source;
  const Index other_source = meet_forward ? back_source : source;
  std::vector<Index> first = trace_back(self, meet, self_source, meet_pred);
  std::vector<Index> second = trace_back(other, g.reverse[meet], other_source, other.pred(g.reverse[meet]));
  if (g.reverse[meet] == other_source) second = {other_source};
  // first: self_source .. meet; second: other_source .. reverse(meet).
  std::vector<Index> tail = reversed_chain(g, second);  // meet .. reverse(other_source)
  first.insert(first.end(), tail.begin() + 1, tail.end());
  path.nodes = meet_forward ? first : reversed_chain(g, first);
  path.cost = mu;
  return path;
}

Path shortest_path(const SearchContext& ctx, SearchWorkspace& ws, SearchWorkspace& ws_back, Index source,
                   Index target, SearchAlgorithm algorithm, double bound, std::size_t budget) {
  if (ctx.is_disabled(source) || ctx.is_disabled(target)) return {};
  switch (algorithm) {
    case SearchAlgorithm::Dijkstra: return search_one(ctx, ws, source, target, false, bound, budget);
    case SearchAlgorithm::AStar: return search_one(ctx, ws, source, target, true, bound, budget);
    case SearchAlgorithm::Bidirectional: return search_two(ctx, ws, ws_back, source, target, bound, budget);
  }
  return {};
}

Path shortest_path_to_set(const SearchContext& ctx, SearchWorkspace& ws, Index source,
                          const std::function<bool(Index)>& is_target, double bound) {
  const ElasticaGraph& g = ctx.graph;
  Path path;
  if (ctx.is_disabled(source)) return path;
  ws.prepare(g.num_nodes());
  MinHeap heap;
  ws.set(source, 0.0, kInvalid);
  heap.push(0.0, source);
  while (!heap.empty()) {
    const Index n = heap.pop().second;
    if (!ws.settle(n)) continue;
    const double d = ws.dist(n);
    if (d >= bound) break;
    if (is_target(n)) {
      path.cost = d;
      path.nodes = n == source ? std::vector<Index>{source} : trace_back(ws, n, source, ws.pred(n));
      return path;
    }
    if ((++ws.settled & kCancelPollMask) == 0 && ctx.check_cancel) ctx.check_cancel();
    for (Index a = g.arc_offsets[n]; a < g.arc_offsets[n + 1]; ++a) {
      const Index m = g.arc_head[a];
      if (ctx.is_disabled(m)) continue;
      const double dm = d + g.arc_weight[a];
      if (dm < ws.dist(m)) {
        ws.set(m, dm, n);
        heap.push(dm, m);
      }
    }
  }
  return path;
}

}  // namespace stripweave
