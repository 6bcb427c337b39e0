// Seed points for automatic weaving: see weave_seeds.h.
#include "stripweave/layout/weave_seeds.h"

#include "stripweave/layout/region_bridges.h"

#include <algorithm>
#include <functional>
#include <numeric>
#include <queue>

namespace stripweave {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Lower the distances `d` by shortest paths from `sources` (distance 0) along
// the edges `allowed` admits. Only improvements propagate, so repeated calls
// grow a multi-source distance field incrementally (farthest-point sampling).
// Per vertex its (neighbour, edge) pairs.
using Adjacency = std::vector<std::vector<std::pair<Index, Index>>>;
Adjacency adjacency(const TriangleMesh& mesh, const MeshTopology& topo) {
  Adjacency adj(mesh.num_vertices());
  for (Index e = 0; e < topo.num_edges(); ++e) {
    adj[topo.edges[e][0]].push_back({topo.edges[e][1], e});
    adj[topo.edges[e][1]].push_back({topo.edges[e][0], e});
  }
  return adj;
}

void relax_from(const TriangleMesh& mesh, const Adjacency& adj, const std::vector<Index>& sources,
                const std::function<bool(Index)>& allowed, std::vector<double>& d) {
  using Item = std::pair<double, Index>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (Index s : sources) {
    d[s] = 0;
    queue.push({0.0, s});
  }
  while (!queue.empty()) {
    const auto [dv, v] = queue.top();
    queue.pop();
    if (dv > d[v]) continue;
    for (const auto& [w, e] : adj[v]) {
      if (!allowed(e)) continue;
      const double nd = dv + (mesh.positions[v] - mesh.positions[w]).norm();
      if (nd < d[w]) {
        d[w] = nd;
        queue.push({nd, w});
      }
    }
  }
}

// The vertex of `candidates` with the largest finite-or-not d (ties: lowest id).
Index farthest(const std::vector<Index>& candidates, const std::vector<double>& d) {
  Index best = kInvalid;
  for (Index v : candidates)
    if (best == kInvalid || d[v] > d[best] || (d[v] == d[best] && v < best)) best = v;
  return best;
}

// Farthest-point sampling of `count` vertices of one vertex set, d holding
// the distance to what is already there (the border; +inf where none).
std::vector<SeedPoint> sample(const TriangleMesh& mesh, const Adjacency& topo, std::vector<Index> vertices,
                              const std::function<bool(Index)>& allowed, std::vector<double>& d, int count) {
  std::vector<SeedPoint> out;
  if (vertices.empty()) return out;
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  for (int k = 0; k < count; ++k) {
    Index v = farthest(vertices, d);
    if (std::isinf(d[v])) {
      // No border: start from the vertex farthest from the lowest-numbered one.
      std::vector<double> scratch(d.size(), kInf);
      relax_from(mesh, topo, {vertices.front()}, allowed, scratch);
      v = farthest(vertices, scratch);
      if (std::isinf(scratch[v])) v = vertices.front();  // an isolated vertex
    } else if (k > 0 && d[v] <= 0) {
      break;  // nothing left away from the border and the earlier seeds
    }
    out.push_back({mesh.positions[v], d[v]});
    relax_from(mesh, topo, {v}, allowed, d);
  }
  return out;
}


// The point halfway along the bridge and the bridge's direction there (over
// up to three edges, smoothing the mesh-edge path's zigzag).
CrossingAnchor middle_of(const TriangleMesh& mesh, const Bridge& b) {
  const auto& p = b.path;
  double walked = 0;
  size_t i = 1;
  for (; i + 1 < p.size(); ++i) {
    const double step = (mesh.positions[p[i]] - mesh.positions[p[i - 1]]).norm();
    if (walked + step >= 0.5 * b.length) break;
    walked += step;
  }
  const Vec3 a = mesh.positions[p[i - 1]], c = mesh.positions[p[i]];
  const double step = (c - a).norm();
  const double t = step > 0 ? std::clamp((0.5 * b.length - walked) / step, 0.0, 1.0) : 0.0;
  const Vec3 along = mesh.positions[p[std::min(i + 1, p.size() - 1)]] - mesh.positions[p[i >= 2 ? i - 2 : 0]];
  return {a + t * (c - a), along.normalized()};
}

// The area-weighted normal of the triangles around vertex v (zero if none).
Vec3 vertex_normal(const TriangleMesh& mesh, const MeshTopology& topo, Index v) {
  Vec3 n = Vec3::Zero();
  for (const Index* t = topo.vertex_triangles.begin(v); t != topo.vertex_triangles.end(v); ++t)
    n += triangle_normal_area2(mesh, *t);
  return n.norm() > 0 ? n.normalized() : n;
}

}  // namespace

std::vector<std::vector<SeedPoint>> region_seed_points(const LoopArrangement& A, const Regions& G, int count) {
  const TriangleMesh& mesh = A.mesh;
  const MeshTopology& topo = A.topology;
  const Index nv = mesh.num_vertices();
  std::vector<double> d(nv, kInf);
  std::vector<Index> border;
  std::vector<std::uint8_t> on_border(nv, 0);
  for (Index e = 0; e < topo.num_edges(); ++e)
    if (A.separates(e))
      for (Index v : topo.edges[e]) on_border[v] = 1;
  for (Index v = 0; v < nv; ++v)
    if (on_border[v]) border.push_back(v);
  const auto inside = [&A](Index e) { return !A.separates(e); };
  const Adjacency adj = adjacency(mesh, topo);
  relax_from(mesh, adj, border, inside, d);

  // Each region's vertices (a border vertex belongs to every region around it).
  std::vector<std::vector<Index>> members(G.regions.size());
  for (Index t = 0; t < mesh.num_triangles(); ++t) {
    const Index r = G.triangle_region[t];
    if (r == kInvalid) continue;
    for (Index v : mesh.triangles[t]) members[r].push_back(v);
  }
  std::vector<std::vector<SeedPoint>> out(G.regions.size());
  for (size_t r = 0; r < members.size(); ++r) out[r] = sample(mesh, adj, members[r], inside, d, count);
  return out;
}

std::vector<std::vector<CrossingAnchor>> crossing_anchors(const LoopArrangement& A, const Regions& G) {
  std::vector<std::vector<CrossingAnchor>> out(G.regions.size());
  for (size_t k = 0; k < A.arcs.size(); ++k) {
    const LoopArc& arc = A.arcs[k];
    const Index r = G.arc_left[k];
    if (r == kInvalid || r != G.arc_right[k] || arc.vertices.size() < 2 || arc.left_triangle == kInvalid) continue;
    const size_t m = arc.vertices.size() / 2;
    const Vec3 a = A.mesh.positions[arc.vertices[m - (m > 0 ? 1 : 0)]];
    const Vec3 b = A.mesh.positions[arc.vertices[std::min(m + 1, arc.vertices.size() - 1)]];
    const Vec3 n = triangle_normal_area2(A.mesh, arc.left_triangle).normalized();
    Vec3 across = n.cross(b - a);
    if (across.norm() == 0) continue;
    out[r].push_back({A.mesh.positions[arc.vertices[m]], across.normalized()});
  }
  return out;
}

std::vector<std::vector<CrossingAnchor>> bridge_anchors(const LoopArrangement& A, const Regions& G, int count) {
  const MeshTopology& topo = A.topology;
  // A red region with two or more boundary cycles: a bridge is the cut that
  // makes it a disc, its pieces are its boundary cycles (all its border). A
  // disc with two or more stretches of open boundary (regions.h): its pieces
  // are those stretches, and the curve across a bridge parts two of them.
  enum class Pieces { None, Border, OpenSides };
  std::vector<Pieces> mode(G.regions.size(), Pieces::None);
  for (size_t r = 0; r < G.regions.size(); ++r) {
    const Region& g = G.regions[r];
    if (g.colour == RegionColour::Red && g.boundaries >= 2) mode[r] = Pieces::Border;
    else if (g.disc && g.open_sides >= 2) mode[r] = Pieces::OpenSides;
  }
  std::vector<RegionEdges> edges(G.regions.size());
  for (Index e = 0; e < topo.num_edges(); ++e) {
    Index seen = kInvalid;
    for (Index t : topo.edge_triangles[e]) {
      const Index r = t == kInvalid ? kInvalid : G.triangle_region[t];
      if (r == kInvalid || r == seen || mode[r] == Pieces::None) continue;
      seen = r;
      if (!A.separates(e)) {
        edges[r].inner.push_back(e);
      } else if (mode[r] == Pieces::Border) {
        edges[r].pieces.push_back(e);
      } else if (!A.on_loop(e) && A.degree[topo.edges[e][0]] <= 2 && A.degree[topo.edges[e][1]] <= 2) {
        // A stretch's own edges, short of its ends: where a loop only touches the
        // boundary, the two stretches it parts share that vertex and would be one piece.
        edges[r].pieces.push_back(e);
      }
    }
  }
  std::vector<std::vector<CrossingAnchor>> out(G.regions.size());
  for (size_t r = 0; r < edges.size(); ++r) {
    if (edges[r].pieces.empty()) continue;
    for (const Bridge& b : shortest_bridges(A, edges[r])) {
      if (b.path.size() < 2 || b.length <= 0 || static_cast<int>(out[r].size()) >= count) continue;
      CrossingAnchor anchor = middle_of(A.mesh, b);
      if (mode[r] == Pieces::OpenSides) {
        // Two stretches are parted by the curve ACROSS the bridge between them
        // (the one along it would join them, as a cut joins an annulus's
        // boundaries, and leave a band on each side with both stretches).
        const Vec3 across = vertex_normal(A.mesh, topo, b.path[b.path.size() / 2]).cross(anchor.direction);
        if (across.norm() == 0) continue;
        anchor.direction = across.normalized();
      }
      out[r].push_back(anchor);
    }
  }
  return out;
}

UncoveredArea largest_uncovered_area(const Surface& surface,
                                     const std::vector<const std::vector<std::uint8_t>*>& covered) {
  const TriangleMesh& mesh = surface.mesh;
  const MeshTopology& topo = surface.topology;
  const Index nt = mesh.num_triangles(), nv = mesh.num_vertices();
  std::vector<std::uint8_t> any(nt, 0);
  for (const auto* c : covered)
    for (Index t = 0; t < nt && t < static_cast<Index>(c->size()); ++t) any[t] |= (*c)[t];

  UncoveredArea out;
  std::vector<double> area(nt);
  for (Index t = 0; t < nt; ++t) {
    const Tri& f = mesh.triangles[t];
    area[t] = 0.5 * (mesh.positions[f[1]] - mesh.positions[f[0]]).cross(mesh.positions[f[2]] - mesh.positions[f[0]]).norm();
    out.surface_area += area[t];
    if (!any[t]) out.total_area += area[t];
  }
  // Edge-connected components of the uncovered triangles; keep the largest.
  std::vector<Index> component(nt, kInvalid);
  std::vector<Index> best_members;
  double best_area = 0;
  for (Index seed = 0; seed < nt; ++seed) {
    if (any[seed] || component[seed] != kInvalid) continue;
    std::vector<Index> members{seed}, stack{seed};
    component[seed] = seed;
    double a = 0;
    while (!stack.empty()) {
      const Index t = stack.back();
      stack.pop_back();
      a += area[t];
      for (Index e : topo.triangle_edges[t])
        for (Index u : topo.edge_triangles[e])
          if (u != kInvalid && !any[u] && component[u] == kInvalid) {
            component[u] = seed;
            members.push_back(u);
            stack.push_back(u);
          }
    }
    if (a > best_area) best_area = a, best_members = std::move(members);
  }
  if (best_members.empty()) return out;
  out.found = true;
  out.area = best_area;

  // Its point farthest from the covered triangles.
  std::vector<double> d(nv, kInf);
  std::vector<Index> sources;
  std::vector<std::uint8_t> is_source(nv, 0);
  for (Index t = 0; t < nt; ++t)
    if (any[t])
      for (Index v : mesh.triangles[t]) is_source[v] = 1;
  for (Index v = 0; v < nv; ++v)
    if (is_source[v]) sources.push_back(v);
  const auto all = [](Index) { return true; };
  const Adjacency adj = adjacency(mesh, topo);
  relax_from(mesh, adj, sources, all, d);
  std::vector<Index> vertices;
  for (Index t : best_members)
    for (Index v : mesh.triangles[t]) vertices.push_back(v);
  const std::vector<SeedPoint> s = sample(mesh, adj, vertices, all, d, 1);
  if (!s.empty()) out.seed = s.front();
  return out;
}

}  // namespace stripweave
