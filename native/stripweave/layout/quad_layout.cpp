// Primalization: the context the steps share, and the steps in order (see
// quad_layout.h and primalization.h).
#include "stripweave/layout/primalization.h"

#include "stripweave/layout/star_refinement.h"
#include "stripweave/surface/creases.h"

#include <limits>
#include <memory>
#include <queue>

namespace stripweave {

namespace {

// Whether the refined triangle t holds the directed edge a -> b.
bool has_directed(const TriangleMesh& m, Index t, Index a, Index b) {
  const Tri& f = m.triangles[t];
  for (int i = 0; i < 3; ++i)
    if (f[i] == a && f[(i + 1) % 3] == b) return true;
  return false;
}

}  // namespace

PrimalContext::PrimalContext(const Surface& s, const LoopArrangement& a, const Regions& g)
    : surface(s), arrangement(a), regions(g), surface_crease(creases_of(s)) {
  const TriangleMesh& m = a.mesh;
  const MeshTopology& rt = a.topology;
  const Index nv = m.num_vertices(), nt = m.num_triangles(), ne = rt.num_edges();

  wedges = cut_wedges(m, rt, [&](Index e) { return a.on_loop(e); });
  wedge_region.assign(wedges.count(), kInvalid);
  for (Index t = 0; t < nt; ++t)
    for (int i = 0; i < 3; ++i) wedge_region[wedges.of(t, i)] = g.triangle_region[t];

  edge_length.resize(ne);
  edge_feature.assign(ne, 0);
  for (Index e = 0; e < ne; ++e) {
    const EdgeKey& k = rt.edges[e];
    edge_length[e] = (m.positions[k[0]] - m.positions[k[1]]).norm();
    edge_feature[e] = g.creases.refined_crease[e];
  }
  vertex_on_loop.assign(nv, 0);
  vertex_on_boundary.assign(nv, 0);
  vertex_crossing.assign(nv, 0);
  for (Index e = 0; e < ne; ++e) {
    for (Index v : rt.edges[e]) {
      vertex_on_loop[v] |= a.on_loop(e);
      vertex_on_boundary[v] |= rt.is_boundary_edge(e);
    }
  }
  for (const ArrangementNode& node : a.nodes) vertex_crossing[node.vertex] = node.crossing();

  // The wedge graph: each triangle side joins the wedges at its two corners.
  std::vector<Index> count(wedges.count() + 1, 0);
  for (Index t = 0; t < nt; ++t)
    for (int i = 0; i < 3; ++i) ++count[wedges.of(t, i) + 1], ++count[wedges.of(t, (i + 1) % 3) + 1];
  for (Index w = 0; w < wedges.count(); ++w) count[w + 1] += count[w];
  wedge_neighbours.offsets = count;
  wedge_neighbours.indices.resize(count.back());
  wedge_neighbour_edge.offsets = count;
  wedge_neighbour_edge.indices.resize(count.back());
  std::vector<Index> fill(count.begin(), count.end() - 1);
  for (Index t = 0; t < nt; ++t) {
    for (int i = 0; i < 3; ++i) {
      const Index p = wedges.of(t, i), q = wedges.of(t, (i + 1) % 3), e = rt.triangle_edges[t][i];
      wedge_neighbours.indices[fill[p]] = q, wedge_neighbour_edge.indices[fill[p]++] = e;
      wedge_neighbours.indices[fill[q]] = p, wedge_neighbour_edge.indices[fill[q]++] = e;
    }
  }
}

std::vector<double> PrimalContext::shortest_paths(const std::vector<Index>& sources,
                                                  const std::function<double(Index)>& cost,
                                                  const std::function<bool(Index)>& blocked,
                                                  std::vector<Index>* pred) const {
  std::vector<double> dist(wedges.count(), std::numeric_limits<double>::infinity());
  if (pred) pred->assign(wedges.count(), kInvalid);
  grow_shortest_paths(sources, cost, blocked, dist, pred, nullptr);
  return dist;
}

void PrimalContext::grow_shortest_paths(const std::vector<Index>& sources, const std::function<double(Index)>& cost,
                                        const std::function<bool(Index)>& blocked, std::vector<double>& dist,
                                        std::vector<Index>* pred, std::vector<Index>* reached) const {
  const double inf = std::numeric_limits<double>::infinity();
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  auto reach = [&](Index w, double d) {
    if (reached && dist[w] == inf) reached->push_back(w);
    dist[w] = d;
  };
  for (Index w : sources) {
    if (w == kInvalid) continue;
    reach(w, 0);
    heap.push({0.0, w});
  }
  while (!heap.empty()) {
    const auto [d, w] = heap.top();
    heap.pop();
    if (d > dist[w]) continue;
    for (Index k = wedge_neighbours.offsets[w]; k < wedge_neighbours.offsets[w + 1]; ++k) {
      const Index x = wedge_neighbours.indices[k];
      const double nd = d + cost(wedge_neighbour_edge.indices[k]);
      // Ties go to the smaller wedge, so that results do not depend on heap order;
      // only across an edge of positive cost (nd > d): over a zero-length edge (two
      // coincident points, as B-rep tessellations leave) two wedges at one distance
      // would each take the other as predecessor, and tracing a path back would
      // never end (it grew until the memory guard stopped it).
      if (nd < dist[x] || (pred && nd == dist[x] && nd > d && w < (*pred)[x] && (*pred)[x] != kInvalid)) {
        if (blocked(x)) continue;
        const bool improved = nd < dist[x];
        reach(x, nd);
        if (pred) (*pred)[x] = w;
        if (improved) heap.push({nd, x});
      }
    }
  }
}

std::pair<Index, Index> PrimalContext::arc_side_wedges(Index k, size_t i) const {
  const TriangleMesh& m = arrangement.mesh;
  const LoopArc& arc = arrangement.arcs[k];
  const size_t n = arc.edges.size();
  const size_t j = i < n ? i : n - 1;
  const Index a = arc.vertices[j], b = arc.vertices[(j + 1) % arc.vertices.size()];
  const auto& et = arrangement.topology.edge_triangles[arc.edges[j]];
  Index left = et[0], right = et[1];
  if (!has_directed(m, left, a, b)) std::swap(left, right);
  const Index x = arc.vertices[i];
  auto wedge = [&](Index t) { return t == kInvalid ? kInvalid : wedges.of(t, corner_of(m, t, x)); };
  return {wedge(left), wedge(right)};
}

QuadLayout build_quad_layout(const Surface& s, LoopArrangement& A, Regions& G,
                             const std::vector<Singularity>& singularities, const std::vector<Vec3>& pins,
                             const std::vector<Symmetry>& symmetries, const std::vector<EdgeRoute>& routes) {
  QuadLayout layout;
  layout.valid = G.valid;
  if (!G.valid) {
    // No primal edges: every crease lies off them.
    layout.crease_off_edges = refined_crease_length(A, G.creases.refined_crease);
    layout.crease_conformity = layout.crease_off_edges > 0 ? 0.0 : 1.0;
    layout.crease_conforming = false;
    layout.defects = find_layout_defects(s, A, layout);
    return layout;
  }
  auto ctx = std::make_unique<PrimalContext>(s, A, G);
  std::vector<Index> vertex_wedge;
  layout.vertices = place_primal_vertices(*ctx, singularities, vertex_wedge);
  pin_primal_vertices(*ctx, pins, layout.vertices, vertex_wedge);
  symmetrize_primal_vertices(*ctx, symmetries, layout.vertices, vertex_wedge);
  for (int round = 0;; ++round) {
    std::vector<std::string> problems;
    const std::vector<ResolvedEdgeRoute> resolved = resolve_edge_routes(*ctx, vertex_wedge, routes, problems);
    layout.edges = route_primal_edges(*ctx, vertex_wedge, resolved, problems);
    const std::vector<Index> crowded =
        round < kStarRounds ? crowded_vertices(*ctx, layout.vertices, layout.edges) : std::vector<Index>{};
    if (crowded.empty() || refine_stars(s, A, G, crowded) == 0) {
      layout.problems = std::move(problems);
      break;
    }
    // The context held the arrangement as it was; the vertices keep their
    // refined vertices, now with more neighbours.
    ctx = std::make_unique<PrimalContext>(s, A, G);
    for (size_t r = 0; r < vertex_wedge.size(); ++r)
      if (vertex_wedge[r] != kInvalid) vertex_wedge[r] = wedge_at(*ctx, layout.vertices[r].refined_vertex, r);
  }
  for (const PrimalEdge& e : layout.edges) {
    ++layout.vertices[e.v0].valence;
    ++layout.vertices[e.v1].valence;
  }
  straighten_primal_edges(*ctx, layout);
  cut_primal_patches(*ctx, layout);
  measure_crease_conformity(*ctx, layout);
  layout.defects = find_layout_defects(s, A, layout, ctx->surface_crease);
  return layout;
}

}  // namespace stripweave
