// Building the elastica graph g and its line graph g' (paper §5.3, §5.5-5.7).
//
// 1. Maps (parallel, per vertex): the local geodesic map of every vertex's
//    k-ring gives the candidate g-edges v->w with length |U_v(w)| and
//    departure angle arg U_v(w) (not to vertices whose geodesic would touch
//    a feature or boundary vertex), the vertex's tangent frame, and how q is
//    evaluated there (principal directions, or the feature/boundary curve).
// 2. Pairing: a g-edge is kept only if both maps see each other's end (they
//    do, as ring membership is symmetric, unless the unfolding failed
//    somewhere) and agree on its length within 5%, so reverse[] is total and
//    the length can be made symmetric.
// 3. Nodes: per vertex, sorted by angle; q_n averaged over both ends.
// 4. Arcs: per node, the successors in the angular window around straight
//    ahead (binary search), weighted by eq. (2).
#include "stripweave/elastica/elastica_graph.h"

#include "stripweave/elastica/local_geodesic_map.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <numeric>
#include <thread>

namespace stripweave {

namespace {

constexpr double kPi = M_PI;
constexpr double kTwoPi = 2 * M_PI;
// 1/|<t, c>| is clamped here: parallel to a feature is "effectively
// forbidden" while weights stay finite floats.
constexpr double kMaxInverseDot = 1e4;
// |v->w| and |w->v| from the two vertices' maps may differ by this fraction.
constexpr double kMaxLengthMismatch = 0.05;

double wrap_pi(double a) {  // to [-pi, pi); the callers' angles are within a few turns
  while (a >= kPi) a -= kTwoPi;
  while (a < -kPi) a += kTwoPi;
  return a;
}

float wrap_2pi_float(double a) {  // to [0, 2 pi), also after rounding to float
  a = std::fmod(a, kTwoPi);
  if (a < 0) a += kTwoPi;
  const float f = static_cast<float>(a);
  return f >= static_cast<float>(kTwoPi) || f < 0 ? 0.0f : f;
}

// How q_p(t) is evaluated at one vertex, as a function of the polar angle of t.
struct VertexAlignment {
  enum Kind : std::uint8_t {
    Principal,   // (|k_min|-|k_max|)^2 (1/max(|cos x|, |sin x|) - 1), x = theta - (angle of d_max)
    CurveAxis,   // feature_weight (1/|sin(theta - tau)| - 1), tau = the curve's tangent (<t,c> = sin)
    CurveEdges,  // feature_weight max over curve edges f of (1/|sin(theta - theta_f)| - 1)
  };
  Kind kind = Principal;
  double weight = 0;
  double axis = 0;
  Index first = 0, count = 0;  // CurveEdges: their range in the edge angle list
};

double inverse_sine(double x) { return std::min(1.0 / std::max(std::abs(std::sin(x)), 1e-300), kMaxInverseDot); }

double evaluate_q(const VertexAlignment& a, const std::vector<float>& edge_angles, double theta) {
  switch (a.kind) {
    case VertexAlignment::Principal: {
      const double x = theta - a.axis;
      return a.weight * (1.0 / std::max(std::abs(std::cos(x)), std::abs(std::sin(x))) - 1.0);
    }
    case VertexAlignment::CurveAxis:
      return a.weight * (inverse_sine(theta - a.axis) - 1.0);
    case VertexAlignment::CurveEdges: {
      double dev = 0;
      for (Index i = a.first; i < a.first + a.count; ++i) dev = std::max(dev, inverse_sine(theta - edge_angles[i]) - 1.0);
      return a.weight * dev;
    }
  }
  return 0;
}

// Eq. (2) for consecutive g-edges of lengths l0, l1 turning by gamma, with
// node alignments q0, q1.
ElasticaGraph::ArcTerms arc_terms_of(double gamma, double l0, double l1, double q0, double q1,
                                     const ElasticaParams& p) {
  const double m = std::max(std::min(l0, l1), 1e-12);
  // gamma / (2 tan(gamma / 2)) -> 1 as gamma -> 0 (a straight continuation
  // runs from midpoint to midpoint: (l0 + l1) / 2).
  // For the usual turns (gamma < 34 deg) its series is exact to 1e-11 and
  // spares the millions of arcs a tan().
  const double h = 0.5 * gamma, h2 = h * h;
  const double f = h < 0.3 ? 1.0 - h2 * (1.0 / 3 + h2 * (1.0 / 45 + h2 * (2.0 / 945 + h2 / 14175))) : h / std::tan(h);
  const double len = m * f + 0.5 * std::abs(l0 - l1);
  return {len, p.alpha * 0.5 * (q0 + q1) * len, p.beta * gamma * gamma / m};
}

void check_params(const ElasticaParams& p) {
  if (p.k < 1 || p.k > 16) throw InputError("elastica graph: k must be between 1 and 16, got " + std::to_string(p.k));
  if (!(p.max_turn_deg > 0 && p.max_turn_deg <= 180))
    throw InputError("elastica graph: the maximum turn must be in (0, 180] degrees, got " +
                     std::to_string(p.max_turn_deg));
  if (!(p.alpha >= 0) || !(p.beta >= 0) || !(p.feature_weight >= 0))
    throw InputError("elastica graph: alpha, beta and the feature weight must not be negative");
}

// Per-vertex results of the map stage, for a contiguous chunk of vertices.
struct Chunk {
  std::vector<Index> count;  // candidate g-edges per vertex of the chunk
  std::vector<Index> head;
  std::vector<float> length, angle;
  std::vector<float> edge_angle;  // CurveEdges angles, in vertex order
};

}  // namespace

std::size_t ElasticaGraph::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return sizeof(*this) + bytes(node_offsets) + bytes(frame) + bytes(normal) + bytes(tail) + bytes(head) +
         bytes(reverse) + bytes(length) + bytes(angle) + bytes(alignment) + bytes(arc_offsets) + bytes(arc_head) +
         bytes(arc_weight);
}

double ElasticaGraph::turn(Index from, Index to) const {
  return std::abs(wrap_pi(double(angle[to]) - double(angle[reverse[from]]) - kPi));
}

Vec3 ElasticaGraph::tangent(const Surface& surface, Index node) const {
  const Index v = tail[node];
  const Vec3 n = normal.empty() ? surface.normal[v] : normal[v];
  const double a = angle[node];
  return std::cos(a) * frame[v] + std::sin(a) * n.cross(frame[v]);
}

ElasticaGraph::ArcTerms ElasticaGraph::arc_terms(Index from, Index to) const {
  return arc_terms_of(turn(from, to), length[from], length[to], alignment[from], alignment[to], params);
}

namespace {

constexpr Index kChunk = 256;  // vertices mapped per task

// ---- 1. maps ----------------------------------------------------------------
// The local geodesic map of each vertex of chunk c: its frame and normal into
// g, its candidate g-edges sorted by angle (ties by head, for determinism)
// and its alignment q into `align` (the curve edges' polar angles from the
// exact 1-ring; a CurveEdges range chunk-local for now).
void map_chunk(const Surface& surface, const ElasticaParams& params, LocalGeodesicMapper& mapper, Index c,
               ElasticaGraph& g, std::vector<VertexAlignment>& align, Chunk& out) {
  const Index nv = surface.mesh.num_vertices();
  const bool aligned = params.boundary == BoundaryMode::Aligned;
  auto is_curve_edge = [&](Index e) {
    return surface.edge_class[e] == EdgeClass::Feature || (aligned && surface.edge_class[e] == EdgeClass::Boundary);
  };
  std::vector<std::pair<float, Index>> order;
  for (Index v = c * kChunk; v < std::min(nv, (c + 1) * kChunk); ++v) {
    const LocalGeodesicMap& m = mapper.compute(v, params.k);
    g.frame[v] = m.e1;
    g.normal[v] = m.normal;
    auto polar = [&](Index i) { return std::atan2(m.u[i].y(), m.u[i].x()); };
    order.clear();
    for (Index i = 1; i < m.size(); ++i)
      if (!m.touches_blocked[i]) order.emplace_back(wrap_2pi_float(polar(i)), i);
    std::sort(order.begin(), order.end(), [&](const auto& x, const auto& y) {
      return x.first != y.first ? x.first < y.first : m.vertex[x.second] < m.vertex[y.second];
    });
    out.count.push_back(static_cast<Index>(order.size()));
    for (const auto& [a, i] : order) {
      out.head.push_back(m.vertex[i]);
      out.length.push_back(static_cast<float>(m.u[i].norm()));
      out.angle.push_back(a);
    }
    VertexAlignment& al = align[v];
    double curve[2] = {0, 0};
    Index ncurve = 0;
    const Index first = static_cast<Index>(out.edge_angle.size());
    for (const Index* w = surface.topology.vertex_neighbours.begin(v); w != surface.topology.vertex_neighbours.end(v);
         ++w) {
      const Index lw = mapper.local(*w);
      if (lw == kInvalid || !is_curve_edge(surface.topology.find_edge(v, *w))) continue;
      const double a = polar(lw);
      if (ncurve < 2) curve[ncurve] = a;
      ++ncurve;
      out.edge_angle.push_back(static_cast<float>(a));
    }
    if (ncurve == 0) {
      out.edge_angle.resize(first);
      al.kind = VertexAlignment::Principal;
      const double anis = std::abs(surface.k_min[v]) - std::abs(surface.k_max[v]);
      const Vec3& dmax = surface.d_max[v];
      const double x = dmax.dot(m.e1), y = dmax.dot(m.e2);
      al.weight = x * x + y * y > 1e-12 ? anis * anis : 0.0;  // no direction: no preference
      al.axis = std::atan2(y, x);
    } else if (ncurve == 2 && std::abs(wrap_pi(curve[1] - curve[0] - kPi)) < kPi / 4) {
      // A curve running through v: c is perpendicular to the mean axis of
      // its two edges (axial mean, so the edges' opposite senses agree).
      out.edge_angle.resize(first);
      al.kind = VertexAlignment::CurveAxis;
      al.weight = params.feature_weight;
      al.axis = 0.5 * std::atan2(std::sin(2 * curve[0]) + std::sin(2 * curve[1]),
                                 std::cos(2 * curve[0]) + std::cos(2 * curve[1]));
    } else {
      // A curve end, a sharp bend of the curve, or a corner where curves meet.
      al.kind = VertexAlignment::CurveEdges;
      al.weight = params.feature_weight;
      al.first = first;
      al.count = ncurve;
    }
  }
}

// Every chunk mapped, on two threads when there are two cores; the caller's
// thread reports progress (and so may throw Cancelled), the helper stops
// when the caller's does.
std::vector<Chunk> map_vertices(const Surface& surface, const ElasticaParams& params, ElasticaGraph& g,
                                std::vector<VertexAlignment>& align, Progress* progress) {
  const Index nv = surface.mesh.num_vertices();
  const GeodesicMapDomain domain(surface);
  g.frame.assign(nv, Vec3::UnitX());
  g.normal.assign(nv, Vec3::UnitZ());
  const Index nchunks = (nv + kChunk - 1) / kChunk;
  std::vector<Chunk> chunks(nchunks);
  std::atomic<Index> next{0}, done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr failure;
  auto work = [&](bool reporting) {
    LocalGeodesicMapper mapper(domain);
    for (;;) {
      if (stop.load()) return;
      const Index c = next++;
      if (c >= nchunks) return;
      map_chunk(surface, params, mapper, c, g, align, chunks[c]);
      const Index d = ++done;
      if (reporting && progress) progress->advance(0.75 * d / nchunks);  // throws Cancelled
      if (!reporting && progress && progress->cancelled()) return;
    }
  };
  const unsigned hw = std::thread::hardware_concurrency();
  std::thread helper;
  if (nchunks > 1 && hw != 1)
    helper = std::thread([&] {
      try {
        work(false);
      } catch (...) {
        stop = true;
        failure = std::current_exception();
      }
    });
  try {
    work(true);
  } catch (...) {
    stop = true;
    if (helper.joinable()) helper.join();
    throw;
  }
  if (helper.joinable()) helper.join();
  if (failure) std::rethrow_exception(failure);
  if (progress) progress->check();
  return chunks;
}

// The chunks gathered into per-vertex candidate lists ("raw" g-edges), the
// chunks released as they go; CurveEdges ranges made global.
struct RawEdges {
  std::vector<Index> offsets;  // per vertex, into the lists below
  std::vector<Index> head;
  std::vector<float> length, angle;
  std::vector<float> edge_angle;  // CurveEdges angles
};

RawEdges gather(std::vector<Chunk>& chunks, Index nv, std::vector<VertexAlignment>& align) {
  RawEdges raw;
  raw.offsets.assign(nv + 1, 0);
  size_t total = 0, total_edges = 0;
  for (const Chunk& c : chunks) total += c.head.size(), total_edges += c.edge_angle.size();
  raw.head.reserve(total);
  raw.length.reserve(total);
  raw.angle.reserve(total);
  raw.edge_angle.reserve(total_edges);
  Index v = 0;
  for (Chunk& c : chunks) {
    const Index edge_base = static_cast<Index>(raw.edge_angle.size());
    for (Index cnt : c.count) {
      raw.offsets[v + 1] = raw.offsets[v] + cnt;
      if (align[v].kind == VertexAlignment::CurveEdges) align[v].first += edge_base;
      ++v;
    }
    raw.head.insert(raw.head.end(), c.head.begin(), c.head.end());
    raw.length.insert(raw.length.end(), c.length.begin(), c.length.end());
    raw.angle.insert(raw.angle.end(), c.angle.begin(), c.angle.end());
    raw.edge_angle.insert(raw.edge_angle.end(), c.edge_angle.begin(), c.edge_angle.end());
    c = Chunk();
  }
  return raw;
}

// ---- 2. pairing ---------------------------------------------------------------
// Per raw entry v->w its reverse w->v, and its node when both maps agree on
// its length (g.node_offsets set); returns the node count.
Index pair_raw_edges(const RawEdges& raw, Index nv, std::vector<Index>& raw_reverse, std::vector<Index>& node_of_raw,
                     ElasticaGraph& g) {
  // by_head: each vertex's raw entries ordered by head, to find w->v from v->w.
  const Index nraw = static_cast<Index>(raw.head.size());
  std::vector<Index> by_head(nraw);
  std::iota(by_head.begin(), by_head.end(), 0);
  for (Index v = 0; v < nv; ++v)
    std::sort(by_head.begin() + raw.offsets[v], by_head.begin() + raw.offsets[v + 1],
              [&](Index a, Index b) { return raw.head[a] < raw.head[b]; });
  auto find_raw = [&](Index v, Index w) {  // the raw entry v->w, or kInvalid
    auto first = by_head.begin() + raw.offsets[v], last = by_head.begin() + raw.offsets[v + 1];
    auto it = std::lower_bound(first, last, w, [&](Index r, Index x) { return raw.head[r] < x; });
    return it != last && raw.head[*it] == w ? *it : kInvalid;
  };
  raw_reverse.assign(nraw, kInvalid);
  node_of_raw.assign(nraw, kInvalid);
  g.node_offsets.assign(nv + 1, 0);
  Index nodes = 0;
  for (Index v = 0; v < nv; ++v) {
    for (Index r = raw.offsets[v]; r < raw.offsets[v + 1]; ++r) {
      const Index rr = find_raw(raw.head[r], v);
      raw_reverse[r] = rr;
      // The two maps measure the same geodesic and agree closely, except
      // where one had to go round a feature vertex that the other's
      // geodesic passed just beside (about 1 pair in 5000 on real parts):
      // such an ambiguous g-edge is left out, in both directions alike.
      const bool agree = rr != kInvalid && std::abs(raw.length[r] - raw.length[rr]) <=
                                               kMaxLengthMismatch * std::min(raw.length[r], raw.length[rr]);
      if (agree) node_of_raw[r] = nodes++;
    }
    g.node_offsets[v + 1] = nodes;
  }
  return nodes;
}

// ---- 3. nodes -------------------------------------------------------------------
void make_nodes(const RawEdges& raw, const std::vector<VertexAlignment>& align, const std::vector<Index>& raw_reverse,
                const std::vector<Index>& node_of_raw, Index nodes, ElasticaGraph& g) {
  const Index nv = static_cast<Index>(raw.offsets.size()) - 1;
  g.tail.resize(nodes);
  g.head.resize(nodes);
  g.reverse.resize(nodes);
  g.length.resize(nodes);
  g.angle.resize(nodes);
  g.alignment.resize(nodes);
  for (Index v = 0; v < nv; ++v) {
    for (Index r = raw.offsets[v]; r < raw.offsets[v + 1]; ++r) {
      const Index n = node_of_raw[r];
      if (n == kInvalid) continue;
      const Index rr = raw_reverse[r], w = raw.head[r];
      g.tail[n] = v;
      g.head[n] = w;
      g.reverse[n] = node_of_raw[rr];
      // Lengths as float sums in a fixed order, so |v->w| == |w->v| exactly.
      const float a = raw.length[r], b = raw.length[rr];
      g.length[n] = 0.5f * (std::min(a, b) + std::max(a, b));
      g.angle[n] = raw.angle[r];
      // q at the tail with the departure tangent, at the head with the
      // arrival tangent (opposite to w's direction towards v); q is
      // pi-periodic, so the reverse node gets the same value.
      const double qa = evaluate_q(align[v], raw.edge_angle, raw.angle[r]);
      const double qb = evaluate_q(align[w], raw.edge_angle, double(raw.angle[rr]) + kPi);
      g.alignment[n] = static_cast<float>(0.5 * (qa + qb));
    }
  }
  // Make the stored alignment bit-identical for both directions.
  for (Index n = 0; n < nodes; ++n)
    if (g.reverse[n] < n) g.alignment[n] = g.alignment[g.reverse[n]];
}

// ---- 4. arcs ----------------------------------------------------------------------
// Calls f(m, gamma) for every successor m of node n (turn gamma <= max_turn),
// in angle order from the right edge of the window.
template <class F>
void for_each_successor(const ElasticaGraph& g, double max_turn, Index n, F&& f) {
  const Index v = g.head[n], back = g.reverse[n];
  const Index b = g.node_offsets[v], e = g.node_offsets[v + 1];
  const double ahead = double(g.angle[back]) + kPi;
  const float* A = g.angle.data();
  auto scan = [&](double lo, double hi) {  // nodes with lo <= angle <= hi, with a little slack
    Index i = static_cast<Index>(std::lower_bound(A + b, A + e, static_cast<float>(lo - 1e-5)) - A);
    for (; i < e && A[i] <= hi + 1e-5; ++i) {
      const double gamma = std::abs(wrap_pi(double(A[i]) - double(A[back]) - kPi));  // == g.turn(n, i), bit for bit
      if (i != back && gamma <= max_turn) f(i, gamma);
    }
  };
  if (max_turn >= kPi - 1e-4) {
    scan(0, kTwoPi);
    return;
  }
  double lo = ahead - max_turn, hi = ahead + max_turn;  // ahead in [pi, 3 pi)
  while (lo >= kTwoPi) lo -= kTwoPi, hi -= kTwoPi;
  if (hi < kTwoPi) {
    scan(lo, hi);
  } else {
    scan(lo, kTwoPi);
    scan(0, hi - kTwoPi);
  }
}

// body(first, last) over two halves of the node range, on two threads when
// there are enough nodes and cores: every node is written by one thread.
template <class Body>
void over_node_halves(Index nodes, Body&& body) {
  const Index half = nodes / 2;
  std::exception_ptr failure;
  std::thread helper;
  const bool two = nodes > 4096 && std::thread::hardware_concurrency() != 1;
  if (two)
    helper = std::thread([&] {
      try {
        body(half, nodes);
      } catch (...) {
        failure = std::current_exception();
      }
    });
  body(0, two ? half : nodes);
  if (helper.joinable()) helper.join();
  if (failure) std::rethrow_exception(failure);
}

// The arcs (CSR): counted, then filled, each pass over node halves.
void make_arcs(const ElasticaParams& params, ElasticaGraph& g, Progress* progress) {
  const Index nodes = static_cast<Index>(g.tail.size());
  const double max_turn = params.max_turn_deg * kPi / 180.0;
  g.arc_offsets.assign(nodes + 1, 0);
  over_node_halves(nodes, [&](Index first, Index last) {
    for (Index n = first; n < last; ++n) {
      Index count = 0;
      for_each_successor(g, max_turn, n, [&](Index, double) { ++count; });
      g.arc_offsets[n + 1] = count;
    }
  });
  std::partial_sum(g.arc_offsets.begin(), g.arc_offsets.end(), g.arc_offsets.begin());
  if (progress) progress->advance(0.9);
  g.arc_head.resize(g.arc_offsets[nodes]);
  g.arc_weight.resize(g.arc_offsets[nodes]);
  over_node_halves(nodes, [&](Index first, Index last) {
    for (Index n = first; n < last; ++n) {
      Index k = g.arc_offsets[n];
      for_each_successor(g, max_turn, n, [&](Index m, double gamma) {
        const ElasticaGraph::ArcTerms t =
            arc_terms_of(gamma, g.length[n], g.length[m], g.alignment[n], g.alignment[m], params);
        g.arc_head[k] = m;
        g.arc_weight[k] = static_cast<float>(t.length + t.alignment + t.curvature);
        ++k;
      });
    }
  });
}

}  // namespace

ElasticaGraph build_elastica_graph(const Surface& surface, const ElasticaParams& params, Progress* progress) {
  check_params(params);
  ElasticaGraph g;
  g.params = params;
  const Index nv = surface.mesh.num_vertices();
  std::vector<VertexAlignment> align(nv);
  {
    RawEdges raw;
    {
      std::vector<Chunk> chunks = map_vertices(surface, params, g, align, progress);
      raw = gather(chunks, nv, align);
    }
    if (progress) progress->advance(0.78);
    std::vector<Index> raw_reverse, node_of_raw;
    const Index nodes = pair_raw_edges(raw, nv, raw_reverse, node_of_raw, g);
    make_nodes(raw, align, raw_reverse, node_of_raw, nodes, g);
  }  // the raw lists are released before the arcs are made
  if (progress) progress->advance(0.85);
  make_arcs(params, g, progress);
  if (progress) progress->advance(1.0);
  return g;
}

}  // namespace stripweave
