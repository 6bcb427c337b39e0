#include "stripweave/elastica/loop_search.h"

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/core/error.h"
#include "stripweave/elastica/radix_heap.h"
#include "stripweave/elastica/shortest_paths.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <thread>
#include <limits>
#include <mutex>
#include <sstream>

namespace stripweave {

namespace {

std::string model_point(const Surface& s, const Vec3& p) {
  const Vec3 q = s.similarity.to_model(p);
  std::ostringstream out;
  out << "(" << q.x() << ", " << q.y() << ", " << q.z() << ")";
  return out.str();
}

double wrap_pi(double a) {
  a = std::fmod(a + M_PI, 2 * M_PI);
  if (a < 0) a += 2 * M_PI;
  return a - M_PI;
}

void append_chain(std::vector<Index>& chain, const std::vector<Index>& piece) {
  // Consecutive pieces share their joining node.
  chain.insert(chain.end(), chain.empty() ? piece.begin() : piece.begin() + 1, piece.end());
}

// The g' nodes that may end an open curve: those arriving at an allowed
// boundary vertex across the boundary, nearer its normal than its tangent.
// A curve meets the open boundary orthogonally (§5.7); a node along the
// boundary, both its ends on it, closed a "curve" of that node alone at no
// cost, which the search prefers to every real one (a range scan's holes
// took 12 of its 18 strips, each clipping a corner of a hole).
std::vector<bool> curve_ends(const Surface& s, const ElasticaGraph& g, const std::vector<bool>& on_boundary,
                             const std::vector<Vec3>& tangent) {
  std::vector<bool> ends(g.num_nodes(), false);
  for (Index x = 0; x < g.num_nodes(); ++x) {
    const Index w = g.head[x];
    if (!on_boundary[w]) continue;
    const Vec3 d = s.mesh.positions[w] - s.mesh.positions[g.tail[x]];
    ends[x] = d.norm() > 0 && std::abs(d.normalized().dot(tangent[w])) < std::sqrt(0.5);
  }
  return ends;
}

}  // namespace

LoopTables loop_tables(const Surface& s, const ElasticaGraph& g) {
  LoopTables t;
  // Loops closer than the reach of one g-edge are the same strip.
  double mean_edge = 0;
  for (const EdgeKey& e : s.topology.edges) mean_edge += (s.mesh.positions[e[0]] - s.mesh.positions[e[1]]).norm();
  mean_edge /= std::max<Index>(1, s.topology.num_edges());
  t.duplicate_tolerance = g.params.k * mean_edge;
  // A node arriving at an open boundary ends a dual curve there (§5.7), but
  // not within two mesh edges of a point where a sharp crease ends on the
  // boundary: that is a corner of the part, where a primal vertex goes
  // (corner_strength.h), and a curve ending on it splits it between two
  // regions, so neither takes it and the primal edge along the boundary
  // turns the corner inside a patch side (a square tube's skewed end left
  // patches over its creases, 2.5 tolerances off). Corners by the turn of
  // the boundary alone do not count here: a scan's boundary zig-zags by
  // more than 30 degrees at many vertices, and refusing ends near all of
  // them left the camel head's neck no place to end curves (3 patches
  // instead of 42).
  std::vector<bool> on_boundary(s.mesh.num_vertices(), false);
  for (const auto& loop : s.boundary_loops)
    for (Index v : loop) on_boundary[v] = true;
  std::vector<Vec3> crease_ends;
  for (Index e = 0; e < s.topology.num_edges(); ++e)
    if (s.edge_class[e] == EdgeClass::Feature)
      for (Index v : s.topology.edges[e])
        if (on_boundary[v]) crease_ends.push_back(s.mesh.positions[v]);
  // Per boundary vertex the boundary's tangent there (zero elsewhere).
  std::vector<Vec3> tangent(s.mesh.num_vertices(), Vec3::Zero());
  for (const auto& loop : s.boundary_loops)
    for (size_t i = 0; i < loop.size(); ++i) {
      const Index v = loop[i];
      bool near_corner = false;
      for (const Vec3& c : crease_ends) near_corner |= (s.mesh.positions[v] - c).norm() < 2 * mean_edge;
      on_boundary[v] = !near_corner;
      const Vec3 d = s.mesh.positions[loop[(i + 1) % loop.size()]] - s.mesh.positions[loop[(i + loop.size() - 1) % loop.size()]];
      if (d.norm() > 0) tangent[v] = d.normalized();
    }
  t.ends_curve = curve_ends(s, g, on_boundary, tangent);
  t.has_boundary = !s.boundary_loops.empty();
  return t;
}

// The number of crease (feature) edges at a surface vertex.
static int crease_edges_at(const Surface& s, Index v) {
  int count = 0;
  for (const Index* n = s.topology.vertex_neighbours.begin(v); n != s.topology.vertex_neighbours.end(v); ++n) {
    const Index e = s.topology.find_edge(v, *n);
    count += e != kInvalid && s.edge_class[e] == EdgeClass::Feature;
  }
  return count;
}

// Whether a direction at polar angle theta (g's frame: on a crease vertex,
// angle 0 runs along the crease) is nearer the crease than across it; an
// anchor asking for it is turned across (resolve_anchor).
static bool along_crease(const Surface& s, Index v, double theta) {
  return std::abs(std::sin(theta)) < std::sqrt(0.5) && crease_edges_at(s, v) == 2;  // the cheap test first
}

Index loop_anchor_node(const Surface& s, const ElasticaGraph& g, const Loop& loop, const Vec3& p) {
  Index best = kInvalid, nearest = loop.nodes.front();
  double best_d = std::numeric_limits<double>::infinity(), nearest_d = best_d;
  for (Index n : loop.nodes) {
    const double d = (s.mesh.positions[g.tail[n]] - p).squaredNorm();
    if (d < nearest_d) nearest_d = d, nearest = n;
    if (d < best_d && !along_crease(s, g.tail[n], g.angle[n])) best_d = d, best = n;
  }
  return best != kInvalid ? best : nearest;
}

ResolvedAnchor resolve_anchor(const SearchContext& ctx, const SurfaceLocator& locator, const Anchor& anchor,
                              double max_distance, int index) {
  const Surface& s = ctx.surface;
  const ElasticaGraph& g = ctx.graph;
  const SurfacePoint3 sp = locator.closest(anchor.point);
  ResolvedAnchor r;
  r.distance = sp.distance;
  if (!(sp.distance <= max_distance)) {
    std::ostringstream msg;
    msg << "anchor " << index + 1 << " at " << model_point(s, anchor.point) << " is "
        << sp.distance * s.similarity.scale << " from the surface (more than "
        << max_distance * s.similarity.scale << "): it is off the part";
    throw InputError(msg.str());
  }
  // The nearest g-node: the closest corner of the triangle under the point.
  const Tri& t = s.mesh.triangles[sp.triangle];
  r.vertex = t[0];
  for (Index v : t)
    if ((s.mesh.positions[v] - sp.point).squaredNorm() < (s.mesh.positions[r.vertex] - sp.point).squaredNorm())
      r.vertex = v;
  const Index v = r.vertex;
  const Index begin = g.node_offsets[v], end = g.node_offsets[v + 1];
  if (anchor.directional()) {
    // The plane of v's polar angles: on a crease, the mean of both sides.
    const Vec3 n = g.normal[v];
    const Vec3 d = anchor.direction - anchor.direction.dot(n) * n;
    if (d.norm() < 1e-6 * anchor.direction.norm()) {
      throw InputError("the direction of anchor " + std::to_string(index + 1) + " at " +
                       model_point(s, anchor.point) + " is perpendicular to the surface");
    }
    const Vec3 e1 = g.frame[v], e2 = n.cross(e1);
    double theta = std::atan2(d.dot(e2), d.dot(e1));
    // A dual loop crosses a crease but never runs along it: the crease must
    // be a primal edge, and primal edges lie between loops, not on them
    // (crease_structure.h, "loop along a crease"); nor can it leave a crease
    // vertex diagonally and close smoothly (it would have to arrive along the
    // crease). On a crease vertex (two crease edges; frame[v] runs along the
    // crease, at polar angle 0) a direction nearer the crease than across it
    // is taken across it (§5.6: curves cross features orthogonally). A
    // crease junction keeps the direction asked for.
    if (along_crease(s, v, theta)) theta = 0.5 * M_PI;
    // The node closest to the direction and the one closest to its opposite:
    // a tangent's sign does not matter.
    for (double want : {theta, theta + M_PI}) {
      Index best = kInvalid;
      double best_gap = 1e9;
      for (Index node = begin; node < end; ++node) {
        const double gap = std::abs(wrap_pi(g.angle[node] - want));
        if (gap < best_gap) best_gap = gap, best = node;
      }
      if (best != kInvalid && !ctx.is_disabled(best) &&
          std::find(r.candidates.begin(), r.candidates.end(), best) == r.candidates.end())
        r.candidates.push_back(best);
    }
    if (r.candidates.empty())
      throw InputError("the direction of anchor " + std::to_string(index + 1) + " at " + model_point(s, anchor.point) +
                       " is disabled: it runs along an existing strip, so no compatible loop can take it");
  } else {
    for (Index node = begin; node < end; ++node)
      if (!ctx.is_disabled(node)) r.candidates.push_back(node);
    r.all_directions = true;
    if (r.candidates.empty())
      throw InputError("every direction at anchor " + std::to_string(index + 1) + " at " +
                       model_point(s, anchor.point) + " is disabled by existing strips");
  }
  return r;
}

void evaluate_loop(const ElasticaGraph& g, Loop& loop) {
  loop.cost = loop.length_term = loop.alignment_term = loop.curvature_term = 0;
  loop.max_turn = 0;
  const size_t n = loop.nodes.size();
  const size_t arcs = loop.closed ? n : (n > 0 ? n - 1 : 0);
  for (size_t i = 0; i < arcs; ++i) {
    const Index from = loop.nodes[i], to = loop.nodes[(i + 1) % n];
    const auto terms = g.arc_terms(from, to);
    loop.length_term += terms.length;
    loop.alignment_term += terms.alignment;
    loop.curvature_term += terms.curvature;
    loop.max_turn = std::max(loop.max_turn, g.turn(from, to));
  }
  std::vector<Index> chain = loop.nodes;
  if (loop.closed && n > 0) chain.push_back(loop.nodes.front());
  loop.cost = chain_cost(g, chain);
}

namespace {

constexpr Index kFromPreviousLayer = -2;

enum class Goal { ReturnToStart, Boundary };

// The layered search (see the header): states (layer, node); layer l means
// anchors 0..l are passed. From the start node (layer 0), the goal is to
// re-enter the start in the last layer (a closed loop), or to arrive at an
// open boundary in the last layer (the forward half of an open curve).
// `fields`, when given, are exact lower bounds of the remaining cost per
// layer and node (see backward_fields); they replace the straight-line
// heuristic and prune every state that cannot beat `bound`.
using Fields = std::vector<std::vector<float>>;

Path layered_search(const SearchContext& ctx, SearchWorkspaces& ws, const std::vector<ResolvedAnchor>& anchors,
                    Index start, Goal goal, double bound, bool guided, const std::vector<bool>& ends_curve,
                    const Fields* fields = nullptr) {
  const ElasticaGraph& g = ctx.graph;
  const Surface& s = ctx.surface;
  const Index n = static_cast<Index>(anchors.size());
  if (static_cast<Index>(ws.layers.size()) < n) ws.layers.resize(n);
  for (Index l = 0; l < n; ++l) ws.layers[l].prepare(g.num_nodes());
  std::vector<std::vector<Index>> next(n);  // sorted candidates of anchor l+1
  for (Index l = 0; l + 1 < n; ++l) {
    next[l] = anchors[l + 1].candidates;
    std::sort(next[l].begin(), next[l].end());
  }
  // A* heuristic: straight-line distance through the remaining anchors, each
  // shortened by half the longest g-edge there (a candidate node's midpoint
  // lies that close to its anchor vertex), times the safety margin.
  auto mid = [&](Index node) { return Vec3(0.5 * (s.mesh.positions[g.tail[node]] + s.mesh.positions[g.head[node]])); };
  std::vector<Vec3> target(n + 1);
  std::vector<double> slack(n + 1, 0.0), rest(n + 2, 0.0);
  for (Index j = 1; j < n; ++j) {
    const Index v = anchors[j].vertex;
    target[j] = s.mesh.positions[v];
    for (Index node = g.node_offsets[v]; node < g.node_offsets[v + 1]; ++node)
      slack[j] = std::max(slack[j], 0.5 * double(g.length[node]));
  }
  target[n] = mid(start);
  const Index last_target = goal == Goal::ReturnToStart ? n : n - 1;
  for (Index j = last_target - 1; j >= 1; --j)
    rest[j] = rest[j + 1] + std::max(0.0, (target[j + 1] - target[j]).norm() - slack[j] - slack[j + 1]);
  auto h = [&](Index layer, Index node) {
    if (fields) return double((*fields)[layer][node]);
    if (!guided || layer + 1 > last_target) return 0.0;
    const Index j = layer + 1;
    return kHeuristicScale * (std::max(0.0, (mid(node) - target[j]).norm() - slack[j]) + rest[j]);
  };

  RadixHeap<std::int64_t> heap;
  auto key = [&](Index layer, Index node) { return std::int64_t(layer) * g.num_nodes() + node; };
  ws.layers[0].set(start, 0.0, kInvalid);
  heap.push(h(0, start), key(0, start));
  double best = kUnreachable;
  Index best_layer = kInvalid, best_node = kInvalid, best_pred = kInvalid;
  std::size_t pops = 0;
  while (!heap.empty()) {
    const auto [k, state] = heap.pop();
    const Index layer = static_cast<Index>(state / g.num_nodes()), x = static_cast<Index>(state % g.num_nodes());
    SearchWorkspace& here = ws.layers[layer];
    if (!here.settle(x)) continue;  // stale entry
    const double d = here.dist(x);
    if (k >= std::min(best, bound)) break;
    if ((++pops & 4095) == 0 && ctx.check_cancel) ctx.check_cancel();
    if (layer == n - 1 && goal == Goal::Boundary && ends_curve[x]) {
      best = d, best_layer = layer, best_node = x;
      break;  // settled in cost order: the first is the cheapest
    }
    if (layer + 1 < n && std::binary_search(next[layer].begin(), next[layer].end(), x) &&
        d < ws.layers[layer + 1].dist(x) && d + h(layer + 1, x) < bound) {
      ws.layers[layer + 1].set(x, d, kFromPreviousLayer);
      heap.push(d + h(layer + 1, x), key(layer + 1, x));
    }
    for (Index a = g.arc_offsets[x]; a < g.arc_offsets[x + 1]; ++a) {
      const Index y = g.arc_head[a];
      if (ctx.is_disabled(y)) continue;
      const double dy = d + g.arc_weight[a];
      if (goal == Goal::ReturnToStart && layer == n - 1 && y == start) {
        if (dy < best) best = dy, best_layer = layer, best_node = start, best_pred = x;  // via x
        continue;
      }
      if (dy < here.dist(y) && !(layer == 0 && y == start)) {
        const double f = dy + h(layer, y);
        if (!(f < std::min(best, bound))) continue;  // cannot lead to a better loop
        here.set(y, dy, x);
        heap.push(f, key(layer, y));
      }
    }
  }
  Path path;
  if (best_node == kInvalid || !(best < bound)) return path;
  path.cost = best;
  // Walk back from a state to the start, through the layers.
  auto trace = [&](Index layer, Index x) {
    std::vector<Index> chain;
    while (true) {
      const Index p = ws.layers[layer].pred(x);
      if (p == kFromPreviousLayer) {
        --layer;
        continue;
      }
      chain.push_back(x);
      if (p == kInvalid) break;
      x = p;
    }
    std::reverse(chain.begin(), chain.end());
    return chain;
  };
  if (goal == Goal::ReturnToStart) {
    path.nodes = trace(best_layer, best_pred);
    path.nodes.push_back(start);
  } else {
    path.nodes = trace(best_layer, best_node);
  }
  return path;
}

// Exact lower bounds for the layered search of closed loops, shared by every
// start: H[n-1](X) = cheapest path from X to any start candidate, and
// H[l](X) = min over c in xi_{l+1} of (path X -> c) + H[l+1](c). Each is one
// multi-source search; by the symmetry of g' the distance *to* a set is a
// forward search from the reversed set. They are consistent (true
// distances), so A* with them is exact, and capped at `cap`: states that
// cannot beat it are never needed.
Fields backward_fields(const SearchContext& ctx, SearchWorkspace& ws, const std::vector<ResolvedAnchor>& anchors,
                       double cap) {
  const ElasticaGraph& g = ctx.graph;
  const Index n = static_cast<Index>(anchors.size());
  const float inf = std::numeric_limits<float>::infinity();
  Fields H(n, std::vector<float>(g.num_nodes(), inf));
  for (Index l = n - 1; l >= 0; --l) {
    const auto& targets = anchors[(l + 1) % n].candidates;
    ws.prepare(g.num_nodes());
    RadixHeap<Index> heap;
    for (Index c : targets) {
      const double c0 = l == n - 1 ? 0.0 : double(H[l + 1][c]);
      if (!(c0 < cap) || ctx.is_disabled(c)) continue;
      // Arriving at c costs its remaining bound; from reverse(c) outward.
      const Index r = g.reverse[c];
      if (c0 < ws.dist(r)) ws.set(r, c0, kInvalid), heap.push(c0, r);
    }
    std::size_t pops = 0;
    while (!heap.empty()) {
      const Index x = heap.pop().second;
      if (!ws.settle(x)) continue;
      const double d = ws.dist(x);
      // x = reverse(X): d is the cheapest cost from X onward.
      H[l][g.reverse[x]] = static_cast<float>(d);
      if ((++pops & 4095) == 0 && ctx.check_cancel) ctx.check_cancel();
      for (Index a = g.arc_offsets[x]; a < g.arc_offsets[x + 1]; ++a) {
        const Index y = g.arc_head[a];
        if (ctx.is_disabled(g.reverse[y])) continue;
        const double dy = d + g.arc_weight[a];
        if (dy < cap && dy < ws.dist(y)) ws.set(y, dy, x), heap.push(dy, y);
      }
    }
  }
  // Float rounding must not make a bound exceed the true remaining cost.
  for (auto& layer : H)
    for (float& v : layer) v = v == inf ? inf : v * (1.0f - 1e-6f);
  return H;
}

// The best loop leaving through one start candidate (closed, or open through
// the boundary), no costlier than `bound`.
Loop best_loop_from(const SearchContext& ctx, SearchWorkspaces& ws, const std::vector<ResolvedAnchor>& anchors,
                    Index start, double bound, const LoopSearchOptions& options, bool open,
                    const std::vector<bool>& ends_curve, std::size_t budget = std::numeric_limits<std::size_t>::max(),
                    bool* aborted = nullptr) {
  const ElasticaGraph& g = ctx.graph;
  const bool guided = options.algorithm != SearchAlgorithm::Dijkstra;
  Loop loop;
  double cost = kUnreachable;
  Path closed = anchors.size() == 1
                    ? shortest_path(ctx, ws.forward, ws.backward, start, start, options.algorithm, bound, budget)
                    : layered_search(ctx, ws, anchors, start, Goal::ReturnToStart, bound, guided, ends_curve);
  if (closed.aborted) {
    if (aborted) *aborted = true;
    return {};
  }
  if (closed.found()) {
    cost = closed.cost;
    loop.nodes.assign(closed.nodes.begin(), closed.nodes.end() - 1);
    loop.closed = true;
  }
  if (open) {
    auto arrives = [&](Index node) { return bool(ends_curve[node]); };
    const double limit = std::min(cost, bound);
    Path forward = layered_search(ctx, ws, anchors, start, Goal::Boundary, limit, guided, ends_curve);
    if (forward.found()) {
      Path backward = shortest_path_to_set(ctx, ws.forward, g.reverse[start], arrives, limit - forward.cost);
      if (backward.found() && forward.cost + backward.cost < limit) {
        cost = forward.cost + backward.cost;
        loop.nodes = reversed_chain(g, backward.nodes);
        append_chain(loop.nodes, forward.nodes);
        loop.closed = false;
      }
    }
  }
  if (cost == kUnreachable) loop.nodes.clear();
  return loop;
}

// Enough starts for the best closed loop through a vertex in any direction.
// A loop leaving at angle a returns along some node n_k and its reversed copy
// (same cost, g' and the mask being symmetric) leaves along reverse(n_k), at
// an angle within max_turn of a + pi. Of any angle a and a + pi +- max_turn,
// one lies in [0, pi + max_turn], so the starts there hold an optimal loop:
// the hover query searches about 58% of the directions, exactly.
std::vector<Index> half_circle_starts(const ElasticaGraph& g, const std::vector<Index>& starts) {
  const double limit = M_PI + g.params.max_turn_deg * M_PI / 180.0 + 1e-6;
  std::vector<Index> kept;
  for (Index s : starts)
    if (g.angle[s] <= limit) kept.push_back(s);
  return kept;
}

// The order in which best_over_starts searches the start directions. Every
// start is still searched (bounded by the best loop so far), so the order
// changes only the work, never the result; what it buys is a tight bound
// early. The cost of the best loop leaving in a direction varies
// continuously with the direction (a loop leaving a few degrees off is the
// same loop bent near the anchor), and on a flat face or a crease, where the
// alignment term is zero in every direction, the given order (by alignment)
// is merely by angle: a point on the handle's flat top searched its 41
// directions from angle 0 while its best loop left at 2.07 rad, every search
// before it bounded by loops up to 1.8 times as costly. So: first a coarse
// pass (the best-aligned start, then one start per max_turn of angle), then
// the start nearest in angle to the cheapest loop found so far. A start whose
// unbounded search was put off comes back once every other start was tried.
class StartSchedule {
 public:
  StartSchedule(const ElasticaGraph& g, const std::vector<Index>& starts) : angle_(starts.size()), state_(starts.size(), kPending) {
    for (size_t i = 0; i < starts.size(); ++i) angle_[i] = g.angle[starts[i]];
    // The coarse pass: starts at least max_turn apart in angle, in the
    // given order (the first is the best aligned).
    const double spacing = g.params.max_turn_deg * M_PI / 180.0;
    for (size_t i = 0; i < starts.size(); ++i) {
      bool apart = true;
      for (size_t j : coarse_) apart = apart && gap(i, j) >= spacing;
      if (apart) coarse_.push_back(i);
    }
  }
  static constexpr size_t kNone = std::numeric_limits<size_t>::max();
  // The next start to search, kNone when all are taken. `put_off` is true
  // for a start that was put off before (its search may run unbounded now).
  size_t next(bool& put_off) {
    std::lock_guard<std::mutex> lock(mutex_);
    put_off = false;
    for (; next_coarse_ < coarse_.size(); ++next_coarse_)
      if (state_[coarse_[next_coarse_]] == kPending) return take(coarse_[next_coarse_++]);
    size_t pick = kNone;
    for (size_t i = 0; i < state_.size(); ++i) {
      if (state_[i] != kPending) continue;
      if (pick == kNone || (best_ != kNone && gap(i, best_) < gap(pick, best_))) pick = i;
    }
    if (pick != kNone) return take(pick);
    for (size_t i = 0; i < state_.size(); ++i)
      if (state_[i] == kPutOff) {
        put_off = true;
        return take(i);
      }
    return kNone;
  }
  // Whether starts other than the put-off ones are left to search.
  bool others_left() {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::find(state_.begin(), state_.end(), kPending) != state_.end();
  }
  void put_off(size_t i) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_[i] = kPutOff;
  }
  // Start i found a loop of this cost.
  void found(size_t i, double cost) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (best_ == kNone || cost < best_cost_) best_ = i, best_cost_ = cost;
  }

 private:
  enum State : std::uint8_t { kPending, kPutOff, kTaken };
  size_t take(size_t i) {
    state_[i] = kTaken;
    return i;
  }
  double gap(size_t i, size_t j) const {
    const double d = std::abs(angle_[i] - angle_[j]);
    return std::min(d, 2 * M_PI - d);
  }
  std::vector<double> angle_;
  std::vector<State> state_;
  std::vector<size_t> coarse_;
  size_t next_coarse_ = 0;
  size_t best_ = kNone;
  double best_cost_ = kUnreachable;
  std::mutex mutex_;
};

// The best loop over all start candidates, each search bounded by the best
// found so far. The starts are shared among the workspaces' threads (both
// cores): the bound is shared too, so every thread prunes with the best loop
// any of them has found. Ties within rounding go to the earlier start in the
// given order (whatever order they were searched in: StartSchedule), and a
// search is only cut when it cannot even tie, so the result does not depend
// on thread timing.
Loop best_over_starts(const SearchContext& ctx, std::vector<SearchWorkspaces>& pool,
                      const std::vector<ResolvedAnchor>& anchors, const std::vector<Index>& starts,
                      const LoopSearchOptions& options, bool open, const std::vector<bool>& ends_curve) {
  constexpr double kTie = 1e-9;
  std::atomic<double> shared_bound{kUnreachable};
  StartSchedule schedule(ctx.graph, starts);
  struct Found {
    Loop loop;
    size_t index = 0;
  };
  std::vector<Found> found(pool.size());
  std::vector<std::exception_ptr> failure(pool.size());
  // While no loop is known, a search runs without a bound and an expensive
  // direction can sweep most of the graph; such a start is put off (at a
  // budget of settled nodes) and searched again, bounded, once a loop is known.
  // Every start is still searched to the end: the result stays exact. Each
  // start put off doubles the budget of the next: where every direction's
  // loop costs more than one budget (a point on the handle's flat top: all
  // 34 directions put off at a fixed 30000, half the query's work), the
  // waste stays within twice the work of the first loop found.
  constexpr std::size_t kUnboundedBudget = 16384;
  std::atomic<int> put_off_count{0};
  auto work = [&](size_t t) {
    try {
      bool was_put_off = false;
      for (size_t i; (i = schedule.next(was_put_off)) != StartSchedule::kNone;) {
        const double bound = shared_bound.load() * (1 + kTie);
        const bool unbounded = bound == kUnreachable;
        bool aborted = false;
        const bool capped = unbounded && !was_put_off && schedule.others_left();
        Loop loop = best_loop_from(ctx, pool[t], anchors, starts[i], bound, options, open, ends_curve,
                                   capped ? kUnboundedBudget << std::min(put_off_count.load(), 20)
                                          : std::numeric_limits<std::size_t>::max(),
                                   &aborted);
        if (aborted) {
          ++put_off_count;
          schedule.put_off(i);
          continue;
        }
        if (loop.nodes.empty()) continue;
        evaluate_loop(ctx.graph, loop);
        schedule.found(i, loop.cost);
        Found& mine = found[t];
        const bool better = mine.loop.nodes.empty() || loop.cost < mine.loop.cost * (1 - kTie) ||
                            (loop.cost <= mine.loop.cost * (1 + kTie) && i < mine.index);
        if (better) mine = {std::move(loop), i};
        for (double b = shared_bound.load(); mine.loop.cost < b && !shared_bound.compare_exchange_weak(b, mine.loop.cost);) {
        }
      }
    } catch (...) {
      failure[t] = std::current_exception();
    }
  };
  std::vector<std::thread> helpers;
  for (size_t t = 1; t < pool.size(); ++t) helpers.emplace_back(work, t);
  work(0);
  for (auto& h : helpers) h.join();
  for (auto& f : failure)
    if (f) std::rethrow_exception(f);
  Found* best = nullptr;
  for (Found& f : found) {
    if (f.loop.nodes.empty()) continue;
    if (!best || f.loop.cost < best->loop.cost * (1 - kTie) ||
        (f.loop.cost <= best->loop.cost * (1 + kTie) && f.index < best->index))
      best = &f;
  }
  return best ? std::move(best->loop) : Loop{};
}

}  // namespace

std::vector<Loop> find_loops(const SearchContext& ctx, const LoopTables& tables, std::vector<SearchWorkspaces>& pool,
                             const std::vector<ResolvedAnchor>& given, int count, const LoopSearchOptions& options) {
  const ElasticaGraph& g = ctx.graph;
  SearchWorkspaces& ws = pool.at(0);
  if (given.empty()) throw InputError("a loop needs at least one anchor");
  const bool open = options.allow_open && tables.has_boundary;
  const std::vector<bool>& ends_curve = tables.ends_curve;
  // A closed loop is a cycle: start it at the anchor with the fewest
  // candidates. An open curve runs from the boundary through the anchors in
  // the given order, so then the first anchor starts.
  std::vector<ResolvedAnchor> anchors = given;
  if (!open) {
    size_t smallest = 0;
    for (size_t i = 1; i < anchors.size(); ++i)
      if (anchors[i].candidates.size() < anchors[smallest].candidates.size()) smallest = i;
    std::rotate(anchors.begin(), anchors.begin() + smallest, anchors.end());
  }
  // Well-aligned directions first: they usually hold the best loop, and the
  // bound it sets cuts the later searches short.
  std::vector<Index> starts = anchors[0].candidates;
  if (count <= 1 && anchors.size() == 1 && !open && anchors[0].all_directions && ctx.mask_symmetric)
    starts = half_circle_starts(g, starts);
  std::stable_sort(starts.begin(), starts.end(), [&](Index a, Index b) { return g.alignment[a] < g.alignment[b]; });

  // The best loop: every start's search bounded by the best so far (exact).
  Loop best;
  double bound = kUnreachable;
  const bool many_starts = anchors.size() > 1 && !open && starts.size() > 2;
  if (many_starts) {
    // Several positional anchors: one loop from the best-aligned start gives
    // an upper bound; capped backward fields then bound every start from
    // below, and the starts are tried cheapest bound first until the bound
    // passes the best loop. Exact, and most directions are never searched.
    // (A start can fail to close any loop, e.g. when the mask blocks it.)
    Loop first;
    for (Index st : starts) {
      first = best_loop_from(ctx, ws, anchors, st, kUnreachable, options, open, ends_curve);
      if (!first.nodes.empty()) break;
    }
    if (first.nodes.empty()) return {};
    evaluate_loop(g, first);
    bound = first.cost;
    best = std::move(first);
    const Fields fields = backward_fields(ctx, ws.forward, anchors, bound * (1 + 1e-9));
    // A start's lower bound: with one anchor the start is itself a target
    // (field 0), so bound through its first arc instead.
    auto lower_bound = [&](Index st) {
      if (anchors.size() > 1) return double(fields[0][st]);
      double lower = kUnreachable;
      for (Index a = g.arc_offsets[st]; a < g.arc_offsets[st + 1]; ++a)
        if (!ctx.is_disabled(g.arc_head[a]))
          lower = std::min(lower, double(g.arc_weight[a]) + fields[0][g.arc_head[a]]);
      return lower;
    };
    std::vector<std::pair<double, Index>> order;
    for (Index st : starts)
      if (const double lower = lower_bound(st); lower < bound) order.emplace_back(lower, st);
    std::sort(order.begin(), order.end());
    for (const auto& [lower, st] : order) {
      if (!(lower < bound)) break;
      Path p = layered_search(ctx, ws, anchors, st, Goal::ReturnToStart, bound, true, ends_curve, &fields);
      if (!p.found()) continue;
      Loop loop;
      loop.nodes.assign(p.nodes.begin(), p.nodes.end() - 1);
      evaluate_loop(g, loop);
      if (loop.cost < bound) bound = loop.cost, best = std::move(loop);
    }
  } else {
    best = best_over_starts(ctx, pool, anchors, starts, options, open, ends_curve);
  }
  if (best.nodes.empty()) return {};
  if (count <= 1) return {best};

  // Alternatives: the best loop through each start, up to a cost cap.
  const double cap = options.max_alternative_cost_ratio * best.cost;
  std::vector<Loop> found{best};
  for (Index s : starts) {
    Loop loop = best_loop_from(ctx, ws, anchors, s, cap, options, open, ends_curve);
    if (loop.nodes.empty()) continue;
    evaluate_loop(g, loop);
    found.push_back(std::move(loop));
  }
  std::stable_sort(found.begin(), found.end(), [](const Loop& a, const Loop& b) { return a.cost < b.cost; });

  // Merge reversed copies and near-duplicates, keep the cheapest of each.
  std::vector<Loop> distinct;
  for (Loop& loop : found) {
    if (static_cast<int>(distinct.size()) >= count) break;
    bool duplicate = false;
    for (const Loop& kept : distinct) duplicate = duplicate || same_loop(ctx.surface, g, loop, kept, tables.duplicate_tolerance);
    if (!duplicate) distinct.push_back(std::move(loop));
  }
  return distinct;
}

Loop best_loop_through(const SearchContext& ctx, const LoopTables& tables, std::vector<SearchWorkspaces>& pool,
                       const ResolvedAnchor& anchor, const LoopSearchOptions& options) {
  std::vector<Loop> loops = find_loops(ctx, tables, pool, {anchor}, 1, options);
  if (loops.empty()) throw InputError("no loop can pass through this point with the current constraints");
  return loops.front();
}

bool same_loop(const Surface& s, const ElasticaGraph& g, const Loop& a, const Loop& b, double tolerance) {
  auto covered = [&](const Loop& x, const Loop& y) {
    const double t2 = tolerance * tolerance;
    for (Index nx : x.nodes) {
      const Vec3& p = s.mesh.positions[g.tail[nx]];
      bool near = false;
      for (Index ny : y.nodes)
        if ((s.mesh.positions[g.tail[ny]] - p).squaredNorm() <= t2) {
          near = true;
          break;
        }
      if (!near) return false;
    }
    return true;
  };
  return covered(a, b) && covered(b, a);
}

}  // namespace stripweave
