// Shortest paths in g' (paper §5.4), output-sensitive: every search stops as
// soon as its targets are settled or its cost bound is passed.
//
// Three interchangeable algorithms for the one-to-one query (their costs are
// equal; tests check it):
//   Dijkstra       plain, from the source
//   AStar          guided by the straight-line distance to the target: the
//                  length term of eq. (2) alone bounds the cost from below,
//                  so |mid(X) - mid(target)| is admissible
//   Bidirectional  from the source forward and from the target backward; g'
//                  weights are symmetric under reversal (w((u,v),(v,w)) =
//                  w((w,v),(v,u))), so the backward search is a forward search
//                  from reverse(target) and a path's reverse costs the same
// A path is a chain of nodes, source first, target last, with at least one
// arc: the path from a node to itself is a loop through it, never empty
// (footnote 2 of the paper). Disabled nodes (the strips' compatibility mask,
// §6.2) are never entered. Long searches poll a cancellation check.
#pragma once

#include "stripweave/elastica/elastica_graph.h"

#include <functional>
#include <limits>

namespace stripweave {

enum class SearchAlgorithm { Dijkstra, AStar, Bidirectional };

constexpr double kUnreachable = std::numeric_limits<double>::infinity();

// A* heuristics use straight-line distances, which never exceed the arc plus
// segment lengths |e'| between the same points; the margin keeps them
// admissible where a local geodesic map shortens a length slightly.
constexpr double kHeuristicScale = 0.95;

struct Path {
  double cost = kUnreachable;
  std::vector<Index> nodes;
  bool aborted = false;  // the search hit its budget before it could decide
  bool found() const { return cost < kUnreachable; }
};

// Per-node scratch space reused across searches (one per thread). A search
// touches a node's distance, stamp and settled mark together, so they share
// one 16-byte slot: one cache miss per relaxation instead of three, which is
// what bounds the speed of searches over g' (millions of random accesses).
// Epoch stamps make a new search O(1) to start.
class SearchWorkspace {
 public:
  void prepare(Index nodes);
  double dist(Index n) const { return slot_[n].stamp == epoch_ ? slot_[n].dist : kUnreachable; }
  Index pred(Index n) const { return pred_[n]; }
  void set(Index n, double d, Index p) {
    slot_[n].stamp = epoch_;
    slot_[n].dist = d;
    pred_[n] = p;
  }
  // Lazy deletion: a node may sit in the queue several times; only its first
  // pop counts. (Comparing keys instead would fail where a monotone queue
  // raised a key.)
  bool settle(Index n) {
    if (slot_[n].settled == epoch_) return false;
    slot_[n].settled = epoch_;
    return true;
  }
  std::size_t settled = 0;  // statistics of the last search
  // Heap bytes held (20 per g' node once prepared).
  std::size_t memory_bytes() const { return slot_.capacity() * sizeof(Slot) + pred_.capacity() * sizeof(Index); }
  // Free the scratch space; the next prepare() allocates it again.
  void release() {
    std::vector<Slot>().swap(slot_);
    std::vector<Index>().swap(pred_);
    epoch_ = 0;
  }

 private:
  struct Slot {
    double dist;
    std::uint32_t stamp, settled;
  };
  std::vector<Slot> slot_;
  std::vector<Index> pred_;
  std::uint32_t epoch_ = 0;
};

// The scratch space of one query: two for the bidirectional search, one per
// anchor layer for the layered search (loop_search.h).
struct SearchWorkspaces {
  SearchWorkspace forward, backward;
  std::vector<SearchWorkspace> layers;
  std::size_t memory_bytes() const;
  void release();
};

struct SearchContext {
  const Surface& surface;
  const ElasticaGraph& graph;
  const std::vector<std::uint8_t>& disabled;  // per node; empty = none
  std::function<void()> check_cancel;         // may throw Cancelled
  // disabled[n] == disabled[reverse[n]] for every n: then every loop's
  // reversed copy is a loop of the same cost (g' is symmetric).
  bool mask_symmetric = true;
  bool is_disabled(Index n) const { return !disabled.empty() && disabled[n]; }
};

// One source to one target (source == target: the cheapest loop through it),
// with costs above `bound` not explored.
// `budget` caps the nodes settled; past it the search stops with
// Path::aborted (used to put off a start that looks expensive until a bound
// is known).
Path shortest_path(const SearchContext& ctx, SearchWorkspace& ws, SearchWorkspace& ws_back, Index source,
                   Index target, SearchAlgorithm algorithm, double bound = kUnreachable,
                   std::size_t budget = std::numeric_limits<std::size_t>::max());

// From the source to the nearest node accepted by `is_target` (e.g. arriving
// at an open boundary).
Path shortest_path_to_set(const SearchContext& ctx, SearchWorkspace& ws, Index source,
                          const std::function<bool(Index)>& is_target, double bound = kUnreachable);

// The exact cost of a node chain (sum of its arcs in double precision);
// kUnreachable if two consecutive nodes are not joined by an arc.
double chain_cost(const ElasticaGraph& graph, const std::vector<Index>& nodes);

// The reverse of a path: reversed order, each node replaced by its reverse.
std::vector<Index> reversed_chain(const ElasticaGraph& graph, const std::vector<Index>& nodes);

}  // namespace stripweave
