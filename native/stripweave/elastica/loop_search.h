// Constrained minimum-cost loops in g' (paper §5.4, §5.7).
//
// Anchors Phi = (phi_0 .. phi_{n-1}) are passed in order. Each anchor is
// resolved to its nearest g-vertex v_i and a candidate set xi_i of outgoing
// nodes: every enabled outgoing node of v_i for a positional anchor, the node
// closest to the direction (and to its opposite: a direction's sign does not
// matter) for a directional one. On a crease vertex a direction nearer the
// crease than across it is taken across it: a dual loop crosses a crease,
// never runs along it (the crease must be a primal edge).
//
// Metagraph (§5.4): metanodes are the candidates, a metaedge (a, b), a in
// xi_i, b in xi_{i+1 mod n}, weighs the shortest g'-path from a to b, and the
// optimal loop is a minimum cycle. With the boundary node "∂" (§5.7), the
// cycle ∂ -> xi_0 -> ... -> xi_{n-1} -> ∂ is an open dual curve.
//
// We solve the same problem without computing every metaedge: a Dijkstra
// over the layered graph whose states are (anchors passed, g' node), where a
// state at a candidate of the next anchor may step to the next layer at no
// cost. A path from (0, s) back to s after the last layer is a cycle of the
// metagraph through s, and the search settles states in cost order, so it
// stops as soon as the optimum is known (output-sensitive), and it can be
// cut at the cost of the best loop found so far. This matters: a metaedge to
// a badly oriented candidate (arriving "backwards") is the most expensive
// path in the graph, and the paper's pairwise searches would pay for it.
// The optimum is the metagraph's: every metagraph cycle is a layered path of
// the same cost and vice versa. Loops may cross themselves, pass an anchor
// more than once, and belong to any homotopy class.
//
// find_loops returns up to `count` distinct loops, cheapest first: the best
// loop leaving through each start candidate, reversed copies and
// near-duplicates merged. With one positional anchor these are the
// alternatives the mouse wheel browses; loops costing more than
// `max_alternative_cost_ratio` times the best are not offered. The best loop
// alone (count = 1) is exact: every start's search is bounded by the best so
// far. best_loop_through is find_loops for one positional anchor and count 1,
// the hover query.
#pragma once

#include "stripweave/elastica/shortest_paths.h"

namespace stripweave {

struct Anchor {
  Vec3 point = Vec3::Zero();      // normalized units
  Vec3 direction = Vec3::Zero();  // zero: positional anchor
  bool directional() const { return direction.squaredNorm() > 0; }
};

struct ResolvedAnchor {
  Index vertex = kInvalid;
  double distance = 0;            // from the anchor point to the surface
  std::vector<Index> candidates;  // xi
  bool all_directions = false;    // positional: xi is every enabled outgoing node
};

struct Loop {
  std::vector<Index> nodes;  // the g' chain; a closed loop does not repeat its first node
  bool closed = true;
  double cost = 0, length_term = 0, alignment_term = 0, curvature_term = 0;
  double max_turn = 0;  // radians, largest turn between consecutive nodes
};

struct LoopSearchOptions {
  SearchAlgorithm algorithm = SearchAlgorithm::Bidirectional;
  bool allow_open = true;  // use ∂ on surfaces with boundary
  double max_alternative_cost_ratio = 6.0;
};

class SurfaceLocator;

// What every query needs of the surface, computed once per session (not on
// the hover path).
struct LoopTables {
  // Per g' node: an open curve may end with it (§5.7): it arrives at the open
  // boundary away from the part's corners, across the boundary rather than
  // along it (nearer its normal than its tangent).
  std::vector<bool> ends_curve;
  bool has_boundary = false;
  double duplicate_tolerance = 0;   // loops whose vertices are all this close are one strip
};
LoopTables loop_tables(const Surface& surface, const ElasticaGraph& graph);

// Project an anchor onto the surface and pick its candidates. Throws
// InputError when the point is farther than max_distance from the surface, or
// when the mask leaves the anchor no candidate.
ResolvedAnchor resolve_anchor(const SearchContext& ctx, const SurfaceLocator& locator, const Anchor& anchor,
                              double max_distance, int anchor_index);

// The node of `loop` nearest to p (normalized units) whose direction an
// anchor keeps: resolve_anchor turns a direction along a crease at a crease
// vertex across it, so an anchor at a node where the loop runs along a crease
// would ask for another loop, often one the mask refuses. The nearest node
// when every node is such. The loop must have nodes.
Index loop_anchor_node(const Surface& surface, const ElasticaGraph& graph, const Loop& loop, const Vec3& p);

// Fill cost terms and max_turn of a loop from its nodes.
void evaluate_loop(const ElasticaGraph& graph, Loop& loop);

// `pool` holds one scratch space per thread the search may use (one or two).
std::vector<Loop> find_loops(const SearchContext& ctx, const LoopTables& tables, std::vector<SearchWorkspaces>& pool,
                             const std::vector<ResolvedAnchor>& anchors, int count,
                             const LoopSearchOptions& options = {});

Loop best_loop_through(const SearchContext& ctx, const LoopTables& tables, std::vector<SearchWorkspaces>& pool,
                       const ResolvedAnchor& anchor, const LoopSearchOptions& options = {});

// Two loops are the same strip when either is a reversed copy of the other or
// every vertex of each lies within `tolerance` of the other (normalized units).
bool same_loop(const Surface& surface, const ElasticaGraph& graph, const Loop& a, const Loop& b, double tolerance);

}  // namespace stripweave
