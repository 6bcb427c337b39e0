// The crease structure of the regions (see the header).
#include "stripweave/layout/crease_structure.h"

#include "stripweave/layout/crease_rims.h"
#include "stripweave/layout/region_bridges.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <unordered_map>

namespace stripweave {

namespace {

// The surface edge a refined edge lies on, or kInvalid. A refined vertex is
// a surface vertex, or lies inside a surface edge, or inside a triangle.
Index surface_edge_under(const Surface& s, const LoopArrangement& A, Index a, Index b) {
  const Index ea = A.original_edge[a], eb = A.original_edge[b];
  const Index oa = A.original_vertex[a], ob = A.original_vertex[b];
  auto on = [&](Index e, Index ov, Index ev) {
    if (ev != kInvalid) return ev == e;
    return ov != kInvalid && (s.topology.edges[e][0] == ov || s.topology.edges[e][1] == ov);
  };
  if (ea != kInvalid) return on(ea, ob, eb) ? ea : kInvalid;
  if (eb != kInvalid) return on(eb, oa, ea) ? eb : kInvalid;
  if (oa != kInvalid && ob != kInvalid) return s.topology.find_edge(oa, ob);
  return kInvalid;
}

// Per refined vertex: the arc it lies inside (kInvalid at nodes and off the loops).
std::vector<Index> vertex_arcs(const LoopArrangement& A) {
  std::vector<Index> arc_of(A.mesh.num_vertices(), kInvalid);
  for (size_t k = 0; k < A.arcs.size(); ++k) {
    const LoopArc& arc = A.arcs[k];
    const size_t first = arc.closed ? 0 : 1, last = arc.closed ? arc.vertices.size() : arc.vertices.size() - 1;
    for (size_t i = first; i < last; ++i) arc_of[arc.vertices[i]] = static_cast<Index>(k);
  }
  return arc_of;
}

// The per-region analysis, one region's crease edges at a time.
struct Analysis {
  const LoopArrangement& A;
  const std::vector<Index>& triangle_region;
  CreaseStructure& out;
  std::vector<Index> arc_of;
  std::vector<std::uint8_t> node_vertex, on_boundary;
  std::vector<std::vector<Index>> region_edges;  // per region, its crease edges off the loops
  std::vector<Index> to_part;  // regions whose split waits for split_between_pieces

  Analysis(const LoopArrangement& a, const std::vector<Index>& tr, CreaseStructure& o, Index nr)
      : A(a), triangle_region(tr), out(o), arc_of(vertex_arcs(a)), region_edges(nr) {
    const Index nv = A.mesh.num_vertices();
    on_boundary.assign(nv, 0);
    node_vertex.assign(nv, 0);
    for (Index e = 0; e < A.topology.num_edges(); ++e)
      if (A.topology.is_boundary_edge(e))
        for (Index v : A.topology.edges[e]) on_boundary[v] = 1;
    for (const ArrangementNode& n : A.nodes) node_vertex[n.vertex] = 1;
  }

  void flag(Index r, CreaseProblem p, Index at, int excess = 1) {
    RegionCreases& rc = out.regions[r];
    rc.excess += excess;
    if (rc.problem != CreaseProblem::None) return;
    rc.problem = p, rc.problem_vertex = at;
  }

  // Loops running along creases: the crease lies between two regions, on no primal edge.
  void loops_along_creases() {
    for (Index e = 0; e < A.topology.num_edges(); ++e) {
      if (!out.refined_crease[e]) continue;
      const auto& et = A.topology.edge_triangles[e];
      if (!A.on_loop(e)) {
        region_edges[triangle_region[et[0]]].push_back(e);
        continue;
      }
      for (Index t : et)
        if (t != kInvalid) flag(triangle_region[t], CreaseProblem::AlongLoop, A.topology.edges[e][0]);
    }
  }

  void analyse(Index r, bool touches_boundary, std::vector<Index>& degree, std::vector<Index>& parent) {
    const std::vector<Index>& edges = region_edges[r];
    RegionCreases& rc = out.regions[r];
    rc.has_crease = !edges.empty();
    if (edges.empty()) return;
    // The region's crease graph: its vertices, degrees and components.
    std::vector<Index> vertices;
    for (Index e : edges)
      for (Index v : A.topology.edges[e]) {
        if (degree[v]++ == 0) vertices.push_back(v), parent[v] = v;
      }
    auto root = [&](Index v) {
      while (parent[v] != v) v = parent[v] = parent[parent[v]];
      return v;
    };
    Index components = static_cast<Index>(vertices.size());
    int cycles = 0;  // independent cycles: E - V + components
    for (Index e : edges) {
      const Index a = root(A.topology.edges[e][0]), b = root(A.topology.edges[e][1]);
      if (a == b) ++cycles;
      else parent[a] = b, --components;
    }
    std::vector<std::pair<Index, Index>> exits;  // (arc, vertex), one per crease edge leaving
    Index boundary_nodes = 0;
    for (Index v : vertices) {
      if (node_vertex[v]) {
        // A loop crossing, or an open curve's end, on the crease: the crease
        // reaches a corner of the region's boundary, where no primal vertex can be.
        flag(r, CreaseProblem::OnCrossing, v);
      } else if (arc_of[v] != kInvalid) {
        for (Index d = 0; d < degree[v]; ++d) exits.push_back({arc_of[v], v});
        if (out.arc_exit[arc_of[v]] == kInvalid) out.arc_exit[arc_of[v]] = v;
        else if (out.arc_exit[arc_of[v]] != v) out.arc_exit[arc_of[v]] = kNoExit;
      } else if (on_boundary[v] || degree[v] != 2) {
        boundary_nodes += on_boundary[v];
        if (rc.node == kInvalid) rc.node = v;
        else flag(r, CreaseProblem::TwoNodes, v);
      }
    }
    std::sort(exits.begin(), exits.end());
    const auto same_arc = [](const auto& a, const auto& b) { return a.first == b.first; };
    const auto twice = std::adjacent_find(exits.begin(), exits.end(), same_arc);
    int repeated = 0;  // exits beyond the first across each arc
    for (size_t i = 1; i < exits.size(); ++i) repeated += same_arc(exits[i - 1], exits[i]);
    Index other_end = kInvalid;  // the second node, or exit, that the problem pairs with the first
    ExitPair same_arc_pair;
    if (rc.problem == CreaseProblem::TwoNodes) other_end = rc.problem_vertex;
    if (twice != exits.end()) {
      flag(r, CreaseProblem::SameArc, twice->second, repeated);
      if (rc.problem == CreaseProblem::SameArc) {
        same_arc_pair = nearest_exits(exits);
        other_end = same_arc_pair.b;
      }
    }
    if (components > 1) {
      Index apart = vertices[0];
      for (Index v : vertices)
        if (root(v) != root(vertices[0])) apart = v;
      flag(r, CreaseProblem::Disconnected, apart, static_cast<int>(components) - 1);
    }
    if (cycles > 0) flag(r, CreaseProblem::Cycle, vertices[0], cycles);
    if (touches_boundary && boundary_nodes == 0) flag(r, CreaseProblem::BoundaryApart, vertices[0]);
    if (rc.problem != CreaseProblem::None) {
      const Index from = rc.problem == CreaseProblem::TwoNodes ? rc.node : rc.problem == CreaseProblem::SameArc
                                                                                  ? same_arc_pair.a
                                                                                  : kInvalid;
      rc.split_vertex =
          from != kInvalid && other_end != kInvalid ? middle_of_path(edges, from, other_end, rc.split_across) : kInvalid;
      if (rc.split_vertex == kInvalid && same_arc_pair.arc != kInvalid)
        rc.split_vertex = middle_of_arc(same_arc_pair, rc.split_across);
      if (rc.split_vertex == kInvalid) {
        rc.split_vertex = rc.problem_vertex;
        // No crease path or arc joins the pair (two nodes on two creases): part
        // the pieces instead (split_between_pieces, once every region is analysed).
        if (components > 1) to_part.push_back(r);
      }
    }
    for (Index v : vertices) degree[v] = 0;
  }

  // split_between_pieces for every region in to_part, their inner edges
  // gathered in one pass over the edges.
  void split_regions_to_part() {
    std::vector<std::uint8_t> marked(region_edges.size(), 0);
    for (Index r : to_part) marked[r] = 1;
    std::vector<std::vector<Index>> inner(region_edges.size());
    for (Index e = 0; e < A.topology.num_edges(); ++e) {
      if (A.separates(e)) continue;
      const Index t = A.topology.edge_triangles[e][0];
      const Index r = t == kInvalid ? kInvalid : triangle_region[t];
      if (r != kInvalid && marked[r]) inner[r].push_back(e);
    }
    for (Index r : to_part) split_between_pieces(r, inner[r]);
  }

  // Crease pieces apart in one region (the two rims of a face between the
  // same loops), or two nodes no crease path in it joins: the loop that parts
  // them runs between the pieces, so the split is the middle of the shortest
  // bridge joining two pieces inside the region (region_bridges.h), and the
  // direction across the bridge there, along the pieces. A vertex of the
  // second piece instead put the seed on a crease, whose best loop runs along
  // it: it parts nothing and leaves the crease on no primal edge. `inner`:
  // the region's edges off the loops.
  void split_between_pieces(Index r, const std::vector<Index>& inner) {
    RegionCreases& rc = out.regions[r];
    const std::vector<Bridge> bridges = shortest_bridges(A, {region_edges[r], inner});
    if (bridges.empty() || bridges.front().path.size() < 2) return;
    Vec3 across = Vec3::Zero();
    const Index v = halfway(bridges.front().path, across);
    if (across.norm() > 0) rc.split_vertex = v, rc.split_across = across;
  }

  // Two exits across one arc, at distinct vertices, that a loop must part:
  // the vertices and their positions along the arc (at_a < at_b).
  struct ExitPair {
    Index arc = kInvalid, a = kInvalid, b = kInvalid;
    size_t at_a = 0, at_b = 0;
  };

  // Of all exits across one arc (exits: (arc, vertex), sorted), the two that
  // are neighbours along their arc with the shortest stretch of arc between
  // them. Every such pair must be parted by a loop crossing the arc between
  // them, and the nearest pair leaves that loop the least choice: between
  // parallel creases a groove apart it must run along them, in the groove,
  // where a loop parting two exits far apart (the two ends of a lid's edge)
  // may take any course, and its best one crosses the other creases of the
  // part (a box's ring of parallel creases). Distinct vertices only: a crease
  // through an arc with the region on both sides leaves across it twice at
  // one vertex, and no loop parts a vertex from itself.
  ExitPair nearest_exits(const std::vector<std::pair<Index, Index>>& exits) const {
    ExitPair best;
    double shortest = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < exits.size();) {
      size_t j = i;
      while (j < exits.size() && exits[j].first == exits[i].first) ++j;
      const Index k = exits[i].first;
      const std::vector<Index>& v = A.arcs[k].vertices;
      std::vector<size_t> at;  // positions of the arc's exits along it
      for (size_t x = i; x < j; ++x) {
        const size_t p = static_cast<size_t>(std::find(v.begin(), v.end(), exits[x].second) - v.begin());
        if (p < v.size()) at.push_back(p);
      }
      std::sort(at.begin(), at.end());
      at.erase(std::unique(at.begin(), at.end()), at.end());
      for (size_t x = 1; x < at.size(); ++x) {
        double gap = 0;
        for (size_t y = at[x - 1]; y < at[x]; ++y) gap += length(v[y], v[y + 1]);
        if (gap < shortest) shortest = gap, best = {k, v[at[x - 1]], v[at[x]], at[x - 1], at[x]};
      }
      i = j;
    }
    return best;
  }

  // The vertex halfway (by length) along the crease path from a to b over
  // `edges` (breadth-first: the crease network between two nodes of one
  // region is a chain or a small tree); kInvalid if they are not joined.
  Index middle_of_path(const std::vector<Index>& edges, Index a, Index b, Vec3& across) const {
    std::unordered_map<Index, std::vector<Index>> next;
    for (Index e : edges) {
      const EdgeKey& k = A.topology.edges[e];
      next[k[0]].push_back(k[1]), next[k[1]].push_back(k[0]);
    }
    std::unordered_map<Index, Index> pred{{a, a}};
    std::vector<Index> queue{a};
    for (size_t i = 0; i < queue.size() && !pred.count(b); ++i)
      for (Index w : next[queue[i]])
        if (pred.emplace(w, queue[i]).second) queue.push_back(w);
    if (!pred.count(b)) return kInvalid;
    std::vector<Index> path{b};
    while (path.back() != a) path.push_back(pred[path.back()]);
    return halfway(path, across);
  }

  // Two creases that leave the region across one arc without meeting in it
  // (a hole's two rims on the wall between two loops through the hole): the
  // loop that parts them crosses that arc between the two exits, so the
  // split is the arc's vertex halfway (by length) between them, and the
  // direction across the arc there (the new loop crosses the old one, which
  // the two exits' pieces lie on either side of).
  Index middle_of_arc(const ExitPair& pair, Vec3& across) const {
    const std::vector<Index>& v = A.arcs[pair.arc].vertices;
    const std::vector<Index> path(v.begin() + pair.at_a, v.begin() + pair.at_b + 1);
    return halfway(path, across);
  }

  // The vertex of a path halfway along it (by length), and the direction
  // across the path there.
  Index halfway(const std::vector<Index>& path, Vec3& across) const {
    double total = 0;
    for (size_t i = 0; i + 1 < path.size(); ++i) total += length(path[i], path[i + 1]);
    double run = 0;
    size_t i = 0;
    while (i + 2 < path.size() && (run += length(path[i], path[i + 1])) < 0.5 * total) ++i;
    across = across_crease(path, i);
    return path[std::min(i + 1, path.size() - 1)];
  }

  // The direction across the crease path at its vertex i + 1, in the mean
  // tangent plane of the crease's two sides there: a loop leaving that way
  // crosses the crease orthogonally (§5.6), as a loop separating the two
  // nodes should. Zero where the path is a single vertex.
  Vec3 across_crease(const std::vector<Index>& path, size_t i) const {
    if (path.size() < 2) return Vec3::Zero();
    const size_t j = std::min(i + 2, path.size() - 1);
    const Vec3 tangent = A.mesh.positions[path[j]] - A.mesh.positions[path[i]];
    const Index e = A.topology.find_edge(path[i], path[i + 1]);
    Vec3 normal = Vec3::Zero();
    for (Index t : A.topology.edge_triangles[e])
      if (t != kInvalid) normal += triangle_normal_area2(A.mesh, t).normalized();
    const Vec3 d = normal.cross(tangent);
    return d.norm() > 0 ? Vec3(d.normalized()) : Vec3::Zero();
  }

  double length(Index a, Index b) const { return (A.mesh.positions[a] - A.mesh.positions[b]).norm(); }

  static constexpr Index kNoExit = kInvalid - 1;
};

}  // namespace

const char* crease_problem_name(CreaseProblem problem) {
  switch (problem) {
    case CreaseProblem::TwoNodes: return "two crease nodes";
    case CreaseProblem::Disconnected: return "crease pieces apart";
    case CreaseProblem::Cycle: return "closed crease";
    case CreaseProblem::SameArc: return "crease crosses one arc twice";
    case CreaseProblem::OnCrossing: return "loop crossing on a crease";
    case CreaseProblem::AlongLoop: return "loop along a crease";
    case CreaseProblem::BoundaryApart: return "crease apart from the boundary";
    case CreaseProblem::RimUncrossed: return "closed crease crossed fewer than twice";
    default: return "none";
  }
}

std::vector<std::uint8_t> refined_crease_edges(const Surface& s, const LoopArrangement& A) {
  std::vector<std::uint8_t> crease(A.topology.num_edges(), 0);
  for (Index e = 0; e < A.topology.num_edges(); ++e) {
    const Index se = surface_edge_under(s, A, A.topology.edges[e][0], A.topology.edges[e][1]);
    crease[e] = se != kInvalid && s.edge_class[se] == EdgeClass::Feature;
  }
  return crease;
}

CreaseStructure crease_structure(const Surface& s, const LoopArrangement& A, const std::vector<Index>& triangle_region,
                                 Index num_regions) {
  CreaseStructure out;
  out.refined_crease = refined_crease_edges(s, A);
  out.regions.assign(num_regions, RegionCreases{});
  out.arc_exit.assign(A.arcs.size(), kInvalid);
  Analysis analysis(A, triangle_region, out, num_regions);
  analysis.loops_along_creases();
  std::vector<std::uint8_t> touches(num_regions, 0);
  for (Index e = 0; e < A.topology.num_edges(); ++e)
    if (A.topology.is_boundary_edge(e)) touches[triangle_region[A.topology.edge_triangles[e][0]]] = 1;
  std::vector<Index> degree(A.mesh.num_vertices(), 0), parent(A.mesh.num_vertices(), kInvalid);
  for (Index r = 0; r < num_regions; ++r) analysis.analyse(r, touches[r], degree, parent);
  // Regions parted across a bridge between crease pieces: one more pass over
  // the edges, skipped when there is none (most assessments).
  if (!analysis.to_part.empty()) analysis.split_regions_to_part();
  for (Index& x : out.arc_exit)
    if (x == Analysis::kNoExit) x = kInvalid;
  for (const CreaseRim& rim : crease_rims(A, out.refined_crease, triangle_region)) {
    if (rim.lack == 0 || rim.region == kInvalid) continue;
    RegionCreases& rc = out.regions[rim.region];
    rc.rim_lack += rim.lack;
    // The region's only problem is the rim: a loop across it is what resolves it.
    if (rc.problem == CreaseProblem::None && rc.split_vertex == kInvalid)
      rc.split_vertex = rim.seed, rc.split_across = rim.across;
  }
  return out;
}

}  // namespace stripweave
