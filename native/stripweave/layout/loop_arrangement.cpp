// The arrangement of a design's dual loops in a refined mesh (see the header).
#include "stripweave/layout/loop_arrangement.h"

#include "stripweave/core/error.h"
#include "stripweave/core/union_find.h"
#include "stripweave/layout/chord_split.h"
#include "stripweave/layout/cut_triangle.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>

namespace stripweave {

namespace {


// A step of a loop between two snapped points ("skeleton points": surface
// vertices, or points inside surface edges).
struct Step {
  Index loop = kInvalid;
  Index path_step = kInvalid;          // the path point it starts from
  Index from = kInvalid, to = kInvalid;  // skeleton points
  Index edge = kInvalid;                // a run along this surface edge, or
  Index triangle = kInvalid;            // a chord of this surface triangle
  std::vector<Index> chain;             // refined vertices from `from` to `to`
};

// The snapped points inside the surface edges, per edge sorted by t.
struct EdgePoints {
  std::vector<Index> offsets;  // per surface edge, into t / id
  std::vector<double> t;
  std::vector<Index> id;       // refined vertex id
};

// Where path point i of a loop goes: a surface vertex, or a point inside a
// surface edge, after snapping. Fills `skeleton[l][i]` with refined vertex
// ids (surface vertices keep their ids; edge points come after them).
EdgePoints snap_points(const Surface& s, const std::vector<LoopPath>& loops,
                       std::vector<std::vector<Index>>& skeleton, LoopArrangement& out) {
  const Index nv = s.mesh.num_vertices(), ne = s.topology.num_edges();
  struct Entry {
    Index edge;
    double t;
    Index loop, point;
  };
  std::vector<Entry> entries;
  skeleton.resize(loops.size());
  for (size_t l = 0; l < loops.size(); ++l) {
    const SurfacePath& p = loops[l].path;
    const size_t n = p.points.size();
    if (p.vertex.size() != n || p.edge.size() != n || p.t.size() != n)
      throw InputError("loop " + std::to_string(l) + ": a path needs a vertex, an edge and a t per point");
    skeleton[l].assign(n, kInvalid);
    for (size_t i = 0; i < n; ++i) {
      if (p.vertex[i] != kInvalid) {
        if (p.vertex[i] < 0 || p.vertex[i] >= nv)
          throw InputError("loop " + std::to_string(l) + ": point " + std::to_string(i) + " names no surface vertex");
        skeleton[l][i] = p.vertex[i];
      } else if (p.edge[i] >= 0 && p.edge[i] < ne && p.t[i] >= 0 && p.t[i] <= 1) {
        entries.push_back({p.edge[i], p.t[i], static_cast<Index>(l), static_cast<Index>(i)});
      } else {
        throw InputError("loop " + std::to_string(l) + ": point " + std::to_string(i) +
                         " is neither at a surface vertex nor inside a surface edge");
      }
    }
  }
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.edge != b.edge ? a.edge < b.edge : a.t < b.t; });

  EdgePoints ep;
  ep.offsets.assign(ne + 1, 0);
  std::vector<double> sum;  // per cluster, the sum of its t (the cluster sits at the mean)
  std::vector<Index> members;
  for (size_t k = 0; k < entries.size();) {
    const Index e = entries[k].edge;
    size_t end = k;
    while (end < entries.size() && entries[end].edge == e) ++end;
    double last = -1;
    for (size_t m = k; m < end; ++m) {
      const Entry& x = entries[m];
      Index id;
      if (x.t < kSnap || x.t > 1 - kSnap) {
        id = s.topology.edges[e][x.t < kSnap ? 0 : 1];
        ++out.snapped_points;
      } else {
        if (ep.offsets[e + 1] == 0 || x.t - last >= kSnap) {
          ep.t.push_back(0);
          ep.id.push_back(nv + static_cast<Index>(ep.id.size()));
          sum.push_back(0);
          members.push_back(0);
          ++ep.offsets[e + 1];
        }
        sum.back() += x.t, ++members.back();
        id = ep.id.back();
        last = x.t;
      }
      skeleton[x.loop][x.point] = id;
    }
    k = end;
  }
  for (size_t c = 0; c < ep.t.size(); ++c) {
    ep.t[c] = sum[c] / members[c];
    out.snapped_points += members[c] > 1 ? members[c] : 0;
  }
  std::partial_sum(ep.offsets.begin(), ep.offsets.end(), ep.offsets.begin());
  return ep;
}


// The snapped points: per refined vertex id past the surface's vertices,
// the surface edge it lies in.
struct SkeletonPoints {
  const Surface& s;
  EdgePoints ep;
  std::vector<Index> point_edge;  // per edge point
  Index nv = 0;

  SkeletonPoints(const Surface& surface, EdgePoints points)
      : s(surface), ep(std::move(points)), point_edge(ep.id.size()), nv(surface.mesh.num_vertices()) {
    for (Index e = 0; e < s.topology.num_edges(); ++e)
      for (Index k = ep.offsets[e]; k < ep.offsets[e + 1]; ++k) point_edge[k] = e;
  }
  Index edge_of(Index x) const { return x < nv ? kInvalid : point_edge[x - nv]; }
  // The closed surface edge holding both skeleton points, or kInvalid.
  Index common_edge(Index a, Index b) const {
    const MeshTopology& topo = s.topology;
    if (a < nv && b < nv) return topo.find_edge(a, b);
    if (a < nv) std::swap(a, b);
    const Index e = edge_of(a);
    if (b < nv) return topo.edges[e][0] == b || topo.edges[e][1] == b ? e : kInvalid;
    return edge_of(b) == e ? e : kInvalid;
  }
  bool triangle_holds(Index t, Index x) const {
    if (x < nv) {
      const Tri& f = s.mesh.triangles[t];
      return f[0] == x || f[1] == x || f[2] == x;
    }
    const auto& te = s.topology.triangle_edges[t];
    const Index e = edge_of(x);
    return te[0] == e || te[1] == e || te[2] == e;
  }
};

// (2) Each loop's steps between its distinct skeleton points, in order;
// `steps_at` per loop its steps [first, last). Opens out.chains.
std::vector<Step> loop_steps(const SkeletonPoints& sk, const std::vector<LoopPath>& loops,
                             const std::vector<std::vector<Index>>& skeleton,
                             std::vector<std::pair<Index, Index>>& steps_at, LoopArrangement& out) {
  const MeshTopology& topo = sk.s.topology;
  std::vector<Step> steps;
  out.chains.resize(loops.size());
  for (size_t l = 0; l < loops.size(); ++l) {
    const bool closed = loops[l].closed;
    out.chains[l].closed = closed;
    std::vector<Index> seq, origin;  // skeleton points without repeats, and the path point each starts at
    for (size_t i = 0; i < skeleton[l].size(); ++i)
      if (seq.empty() || seq.back() != skeleton[l][i]) seq.push_back(skeleton[l][i]), origin.push_back(static_cast<Index>(i));
    if (closed)
      while (seq.size() > 1 && seq.back() == seq.front()) seq.pop_back(), origin.pop_back();
    const Index begin = static_cast<Index>(steps.size());
    if (seq.size() >= 2) {
      const size_t count = closed ? seq.size() : seq.size() - 1;
      for (size_t i = 0; i < count; ++i) {
        Step st;
        st.loop = static_cast<Index>(l);
        st.path_step = origin[i];
        st.from = seq[i];
        st.to = seq[(i + 1) % seq.size()];
        st.edge = sk.common_edge(st.from, st.to);
        if (st.edge == kInvalid) {
          const Index holder = st.from >= sk.nv ? st.from : st.to;
          if (holder >= sk.nv)
            for (Index t : topo.edge_triangles[sk.edge_of(holder)])
              if (t != kInvalid && sk.triangle_holds(t, st.from) && sk.triangle_holds(t, st.to)) st.triangle = t;
          if (st.triangle == kInvalid)
            throw InputError("loop " + std::to_string(l) + ": path points " + std::to_string(origin[i]) + " and " +
                             std::to_string(origin[(i + 1) % seq.size()]) + " share no triangle");
        }
        steps.push_back(std::move(st));
      }
    }
    steps_at.emplace_back(begin, static_cast<Index>(steps.size()));
  }
  return steps;
}

// The chord steps of each surface triangle (CSR over the steps).
struct TriangleChords {
  std::vector<Index> offsets, steps;
};

TriangleChords chords_per_triangle(const std::vector<Step>& steps, Index nt) {
  TriangleChords c;
  c.offsets.assign(nt + 1, 0);
  for (const Step& st : steps)
    if (st.triangle != kInvalid) ++c.offsets[st.triangle + 1];
  std::partial_sum(c.offsets.begin(), c.offsets.end(), c.offsets.begin());
  c.steps.resize(c.offsets[nt]);
  std::vector<Index> fill(c.offsets.begin(), c.offsets.end() - 1);
  for (Index k = 0; k < static_cast<Index>(steps.size()); ++k)
    if (steps[k].triangle != kInvalid) c.steps[fill[steps[k].triangle]++] = k;
  return c;
}

// (3) Triangle t cut by its chords in its own plane (corner 0 at the
// origin, side 0 along x): its pieces and new vertices appended to out,
// each of its chord steps given its chain of refined vertices.
void split_triangle(const SkeletonPoints& sk, const TriangleChords& chords, Index t, std::vector<Step>& steps,
                    LoopArrangement& out) {
  const auto& P = sk.s.mesh.positions;
  const MeshTopology& topo = sk.s.topology;
  const EdgePoints& ep = sk.ep;
  const Tri& f = sk.s.mesh.triangles[t];
  const auto& te = topo.triangle_edges[t];
  const Vec3 ex = (P[f[1]] - P[f[0]]).normalized();
  Vec3 ey = (P[f[1]] - P[f[0]]).cross(P[f[2]] - P[f[0]]).cross(ex);
  ey = ey.norm() > 0 ? Vec3(ey.normalized()) : Vec3(ex.unitOrthogonal());
  auto to2 = [&](const Vec3& x) { return Vec2((x - P[f[0]]).dot(ex), (x - P[f[0]]).dot(ey)); };
  ChordSplitInput in;
  in.corners = {to2(P[f[0]]), to2(P[f[1]]), to2(P[f[2]])};
  std::vector<Index> global;  // per boundary position of the triangle, its refined vertex
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    in.corner_at[k] = static_cast<Index>(in.boundary.size());
    in.boundary.push_back(in.corners[k]);
    global.push_back(f[k]);
    const Index e = te[k];
    const bool along = topo.edges[e][0] == f[k];
    const Index b = ep.offsets[e], n = ep.offsets[e + 1] - b;
    const Vec2 a2 = in.corners[k], b2 = in.corners[(k + 1) % 3];
    longest = std::max(longest, (b2 - a2).norm());
    for (Index j = 0; j < n; ++j) {
      const Index q = b + (along ? j : n - 1 - j);
      const double tau = along ? ep.t[q] : 1 - ep.t[q];
      in.boundary.push_back((1 - tau) * a2 + tau * b2);
      global.push_back(ep.id[q]);
    }
  }
  auto local = [&](Index x) {
    const auto it = std::find(global.begin(), global.end(), x);
    if (it == global.end()) throw std::logic_error("build_loop_arrangement: a chord end is not on its triangle");
    return static_cast<Index>(it - global.begin());
  };
  const Index first = chords.offsets[t], last = chords.offsets[t + 1];
  for (Index k = first; k < last; ++k)
    in.chords.push_back({local(steps[chords.steps[k]].from), local(steps[chords.steps[k]].to)});
  in.tolerance = kSnap * longest;
  const ChordSplit split = split_by_chords(in);
  out.star_triangles += split.star;

  for (const Vec2& q : split.points) {
    global.push_back(static_cast<Index>(out.mesh.positions.size()));
    out.mesh.positions.push_back(P[f[0]] + q.x() * ex + q.y() * ey);
    out.original_vertex.push_back(kInvalid);
    out.original_edge.push_back(kInvalid);
  }
  for (const auto& tri : split.triangles) {
    out.mesh.triangles.push_back({global[tri[0]], global[tri[1]], global[tri[2]]});
    out.parent_triangle.push_back(t);
  }
  for (Index k = first; k < last; ++k) {
    Step& st = steps[chords.steps[k]];
    st.chain.clear();
    for (Index x : split.chord_vertices[k - first]) st.chain.push_back(global[x]);
  }
}

// (3) The refined mesh: the surface's vertices, the snapped edge points, and
// every triangle with chords or points on its sides split; then its topology.
void refine_mesh(const SkeletonPoints& sk, const TriangleChords& chords, std::vector<Step>& steps, LoopArrangement& out) {
  const auto& P = sk.s.mesh.positions;
  const MeshTopology& topo = sk.s.topology;
  const EdgePoints& ep = sk.ep;
  const Index nv = sk.nv, nt = sk.s.mesh.num_triangles();
  out.mesh.positions.assign(P.begin(), P.end());
  out.original_vertex.resize(nv);
  std::iota(out.original_vertex.begin(), out.original_vertex.end(), 0);
  out.original_edge.assign(nv, kInvalid);
  for (Index k = 0; k < static_cast<Index>(ep.id.size()); ++k) {
    const EdgeKey& e = topo.edges[sk.point_edge[k]];
    out.mesh.positions.push_back((1 - ep.t[k]) * P[e[0]] + ep.t[k] * P[e[1]]);
    out.original_vertex.push_back(kInvalid);
    out.original_edge.push_back(sk.point_edge[k]);
  }
  out.mesh.triangles.reserve(nt + 4 * steps.size());
  out.parent_triangle.reserve(nt + 4 * steps.size());
  for (Index t = 0; t < nt; ++t) {
    const bool has_chords = chords.offsets[t + 1] > chords.offsets[t];
    bool has_points = false;
    for (Index e : topo.triangle_edges[t]) has_points |= ep.offsets[e + 1] > ep.offsets[e];
    if (has_chords || has_points) {
      split_triangle(sk, chords, t, steps, out);
    } else {
      out.mesh.triangles.push_back(sk.s.mesh.triangles[t]);
      out.parent_triangle.push_back(t);
    }
  }
  out.topology = MeshTopology::build(out.mesh);
}

// (4) Each loop's chain of refined vertices and edges, and each chain edge's
// label, indexed per refined edge.
void chains_and_labels(const SkeletonPoints& sk, const std::vector<std::pair<Index, Index>>& steps_at,
                       std::vector<Step>& steps, LoopArrangement& out) {
  const MeshTopology& topo = sk.s.topology;
  const MeshTopology& rt = out.topology;
  std::vector<std::pair<Index, Index>> labelled;  // (refined edge, label)
  for (size_t l = 0; l < out.chains.size(); ++l) {
    LoopChain& chain = out.chains[l];
    std::vector<Index> chain_steps;  // per chain edge, its step
    for (Index k = steps_at[l].first; k < steps_at[l].second; ++k) {
      Step& st = steps[k];
      if (st.triangle == kInvalid) {
        // A run along surface edge e: its refined pieces between the two points.
        const Index e = st.edge;
        std::vector<Index> row{topo.edges[e][0]};
        for (Index q = sk.ep.offsets[e]; q < sk.ep.offsets[e + 1]; ++q) row.push_back(sk.ep.id[q]);
        row.push_back(topo.edges[e][1]);
        const auto i = std::find(row.begin(), row.end(), st.from) - row.begin();
        const auto j = std::find(row.begin(), row.end(), st.to) - row.begin();
        st.chain.clear();
        if (i <= j) st.chain.assign(row.begin() + i, row.begin() + j + 1);
        else st.chain.assign(row.rbegin() + (row.size() - 1 - i), row.rbegin() + (row.size() - j));
      }
      for (size_t m = chain.vertices.empty() ? 0 : 1; m < st.chain.size(); ++m) chain.vertices.push_back(st.chain[m]);
      for (size_t m = 0; m + 1 < st.chain.size(); ++m) chain_steps.push_back(st.path_step);
    }
    if (chain.closed && chain.vertices.size() > 1 && chain.vertices.back() == chain.vertices.front())
      chain.vertices.pop_back();
    const size_t n = chain.vertices.size();
    const size_t edges = n < 2 ? 0 : chain.closed ? n : n - 1;
    for (size_t i = 0; i < edges; ++i) {
      const Index a = chain.vertices[i], b = chain.vertices[(i + 1) % n];
      const Index e = rt.find_edge(a, b);
      if (e == kInvalid) throw std::logic_error("build_loop_arrangement: a loop's pieces are not refined edges");
      chain.edges.push_back(e);
      LoopLabel label;
      label.loop = static_cast<Index>(l);
      label.position = static_cast<Index>(i);
      label.step = chain_steps[i];
      label.forward = rt.edges[e][0] == a;
      labelled.emplace_back(e, static_cast<Index>(out.labels.size()));
      out.labels.push_back(label);
    }
  }
  std::sort(labelled.begin(), labelled.end());
  out.edge_labels.offsets.assign(rt.num_edges() + 1, 0);
  for (const auto& [e, _] : labelled) ++out.edge_labels.offsets[e + 1];
  std::partial_sum(out.edge_labels.offsets.begin(), out.edge_labels.offsets.end(), out.edge_labels.offsets.begin());
  for (const auto& [_, label] : labelled) out.edge_labels.indices.push_back(label);
}

// (4) The arrangement graph: degrees, nodes, node-less cycles, and the
// graph's vertex and edge counts once each run of degree-2 vertices is
// merged into one edge (which keeps V - E). Returns per refined vertex its
// node, or kInvalid.
std::vector<Index> arrangement_graph(LoopArrangement& out) {
  const MeshTopology& rt = out.topology;
  const Index rv = out.mesh.num_vertices();
  out.degree.assign(rv, 0);
  UnionFind components(rv);
  Index graph_edge_pieces = 0;
  for (Index e = 0; e < rt.num_edges(); ++e) {
    if (!out.separates(e)) continue;
    ++out.degree[rt.edges[e][0]], ++out.degree[rt.edges[e][1]];
    components.unite(rt.edges[e][0], rt.edges[e][1]);
    ++graph_edge_pieces;
  }
  std::vector<Index> passes(rv, 0);
  for (const LoopChain& c : out.chains)
    for (Index v : c.vertices) ++passes[v];
  std::vector<Index> node_of(rv, kInvalid);
  std::vector<std::uint8_t> component_has_node(rv, 0);
  Index graph_vertex_pieces = 0;
  for (Index v = 0; v < rv; ++v) {
    if (out.degree[v] == 0) continue;
    ++graph_vertex_pieces;
    if (out.degree[v] == 2) continue;
    node_of[v] = static_cast<Index>(out.nodes.size());
    ArrangementNode node;
    node.vertex = v;
    node.degree = out.degree[v];
    node.passes = passes[v];
    out.nodes.push_back(node);
    out.crossings += node.crossing();
    component_has_node[components.find(v)] = 1;
  }
  Index nodeless_cycles = 0;
  for (Index v = 0; v < rv; ++v)
    if (out.degree[v] > 0 && components.find(v) == v && !component_has_node[v]) ++nodeless_cycles;
  out.graph_vertices = static_cast<Index>(out.nodes.size()) + nodeless_cycles;
  out.graph_edges = out.graph_vertices - (graph_vertex_pieces - graph_edge_pieces);
  return node_of;
}

// The triangles on either side of an arc's first edge.
void arc_sides(const LoopArrangement& out, LoopArc& arc) {
  const Index e = arc.edges.front(), a = arc.vertices[0];
  for (Index t : out.topology.edge_triangles[e]) {
    if (t == kInvalid) continue;
    const Tri& f = out.mesh.triangles[t];
    const int i = f[0] == a ? 0 : f[1] == a ? 1 : 2;
    const bool left = f[(i + 1) % 3] == arc.vertices[1 % arc.vertices.size()];
    (left ? arc.left_triangle : arc.right_triangle) = t;
  }
}

// (4) Arcs: each chain cut at the nodes (and an open chain at its ends); a
// closed chain through no node is one closed arc.
void cut_arcs(const std::vector<Index>& node_of, LoopArrangement& out) {
  for (size_t l = 0; l < out.chains.size(); ++l) {
    const LoopChain& c = out.chains[l];
    const Index n = static_cast<Index>(c.vertices.size());
    if (c.edges.empty()) continue;
    std::vector<Index> cuts;
    for (Index i = 0; i < n; ++i)
      if (node_of[c.vertices[i]] != kInvalid || (!c.closed && (i == 0 || i == n - 1))) cuts.push_back(i);
    if (c.closed && cuts.empty()) {
      LoopArc arc;
      arc.loop = static_cast<Index>(l);
      arc.vertices = c.vertices;
      arc.edges = c.edges;
      arc.closed = true;
      arc_sides(out, arc);
      out.arcs.push_back(std::move(arc));
      continue;
    }
    const Index pieces = c.closed ? static_cast<Index>(cuts.size()) : static_cast<Index>(cuts.size()) - 1;
    for (Index k = 0; k < pieces; ++k) {
      const Index from = cuts[k];
      const Index to = k + 1 < static_cast<Index>(cuts.size()) ? cuts[k + 1] : cuts[0] + n;
      LoopArc arc;
      arc.loop = static_cast<Index>(l);
      for (Index i = from; i <= to; ++i) arc.vertices.push_back(c.vertices[i % n]);
      for (Index i = from; i < to; ++i) arc.edges.push_back(c.edges[i % n]);
      arc_sides(out, arc);
      const Index id = static_cast<Index>(out.arcs.size());
      for (Index end : {arc.vertices.front(), arc.vertices.back()})
        if (node_of[end] != kInvalid) out.nodes[node_of[end]].arcs.push_back(id);
      out.arcs.push_back(std::move(arc));
    }
  }
}

// (4) Chains and labels, the graph and the arcs of the refined mesh, made
// afresh (after (5) they are made again on the split mesh).
void link_loops(const SkeletonPoints& sk, const std::vector<std::pair<Index, Index>>& steps_at,
                std::vector<Step>& steps, LoopArrangement& out) {
  for (LoopChain& c : out.chains) c.vertices.clear(), c.edges.clear();
  out.labels.clear();
  out.edge_labels = Csr();
  out.nodes.clear();
  out.arcs.clear();
  out.crossings = 0;
  chains_and_labels(sk, steps_at, steps, out);
  cut_arcs(arrangement_graph(out), out);
}

// (5) Arcs that are one refined edge between two nodes: three loops nearly
// concurrent inside one triangle cut such a sliver of an arc out of the
// chord in the middle. The primal edge dual to an arc crosses it at an inner
// vertex (primal_edges.cpp), and such an arc has none: its edge was lost,
// the triangular region's vertex kept two of its three edges (valence 2) and
// the patches at the arc's two crossings lost a side each. Every chord piece
// that is such an arc, with a region on both sides, is split at its midpoint
// (each triangle on it cut in two) and the chord steps through it take the
// midpoint; the topology is rebuilt, and the caller links the loops again
// (link_loops), so the arc has the midpoint inside. Returns whether any was.
bool split_bare_arcs(std::vector<Step>& steps, LoopArrangement& out) {
  const MeshTopology& old = out.topology;
  std::vector<std::uint8_t> bare(old.num_edges(), 0);
  bool any = false;  // almost never: then the steps are not walked (every assessment builds an arrangement)
  for (const LoopArc& arc : out.arcs)
    if (!arc.closed && arc.edges.size() == 1 && arc.left_triangle != kInvalid && arc.right_triangle != kInvalid)
      bare[arc.edges[0]] = 1, any = true;
  if (!any) return false;
  // Only chord pieces: a run along a surface edge takes its refined pieces
  // from that edge's snapped points (chains_and_labels), which a midpoint is not.
  std::vector<Index> split;
  for (const Step& st : steps)
    if (st.triangle != kInvalid)
      for (size_t i = 0; i + 1 < st.chain.size(); ++i) {
        const Index e = old.find_edge(st.chain[i], st.chain[i + 1]);
        if (bare[e]) split.push_back(e);
      }
  if (split.empty()) return false;
  // Midpoints numbered in the order of their edges' ends (deterministic).
  std::sort(split.begin(), split.end(), [&](Index x, Index y) { return old.edges[x] < old.edges[y]; });
  split.erase(std::unique(split.begin(), split.end()), split.end());
  TriangleMesh& m = out.mesh;
  std::vector<Index> mid_of(old.num_edges(), kInvalid);  // per refined edge, its midpoint
  for (const Index e : split) {
    mid_of[e] = m.num_vertices();
    m.positions.push_back(0.5 * (m.positions[old.edges[e][0]] + m.positions[old.edges[e][1]]));
    out.original_vertex.push_back(kInvalid);
    out.original_edge.push_back(kInvalid);  // a chord lies inside its surface triangle
  }
  for (Step& st : steps) {
    if (st.triangle == kInvalid || st.chain.empty()) continue;
    std::vector<Index> chain{st.chain[0]};
    for (size_t i = 0; i + 1 < st.chain.size(); ++i) {
      const Index mid = mid_of[old.find_edge(st.chain[i], st.chain[i + 1])];
      if (mid != kInvalid) chain.push_back(mid);
      chain.push_back(st.chain[i + 1]);
    }
    st.chain = std::move(chain);
  }
  // The sides of a sliver region can all be bare arcs: a triangle may be cut on several sides.
  for (const Index t : cut_triangles(m, old, mid_of)) out.parent_triangle.push_back(out.parent_triangle[t]);
  out.topology = MeshTopology::build(m);
  return true;
}

}  // namespace

LoopArrangement build_loop_arrangement(const Surface& s, const std::vector<LoopPath>& loops) {
  LoopArrangement out;
  std::vector<std::vector<Index>> skeleton;
  const SkeletonPoints sk(s, snap_points(s, loops, skeleton, out));  // (1)
  std::vector<std::pair<Index, Index>> steps_at;
  std::vector<Step> steps = loop_steps(sk, loops, skeleton, steps_at, out);  // (2)
  refine_mesh(sk, chords_per_triangle(steps, s.mesh.num_triangles()), steps, out);  // (3)
  link_loops(sk, steps_at, steps, out);  // (4)
  if (split_bare_arcs(steps, out)) link_loops(sk, steps_at, steps, out);  // (5)
  return out;
}

}  // namespace stripweave
