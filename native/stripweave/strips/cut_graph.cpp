// The cut graph of a cross field and the combed field (see the header).
#include "stripweave/strips/cut_graph.h"

#include <cmath>
#include <numeric>
#include <stdexcept>

namespace stripweave {

namespace {

int mod4(int r) { return ((r % 4) + 4) % 4; }

// The field of a triangle as a unit tangent vector: the stored direction,
// projected onto the triangle's plane (it is tangent up to rounding), or the
// frame's first axis if the direction is missing.
Vec3 field_direction(const CrossField& field, const Vec3& n, Index t) {
  Vec3 d = field.direction[t] - field.direction[t].dot(n) * n;
  if (d.squaredNorm() < 1e-24) d = field.frame_x[t] - field.frame_x[t].dot(n) * n;
  return d.normalized();
}

// The hinge map about an edge with unit direction a: a tangent vector of the
// triangle with normal n0 rotated into the plane of the triangle with normal
// n1, keeping its components along and across the edge (parallel transport
// of the discrete Levi-Civita connection).
Vec3 transport(const Vec3& x, const Vec3& a, const Vec3& n0, const Vec3& n1) {
  return x.dot(a) * a + x.dot(n0.cross(a)) * n1.cross(a);
}

// Vertex -> incident edges, as CSR.
Csr vertex_edges(const MeshTopology& topo, Index num_vertices) {
  Csr c;
  c.offsets.assign(num_vertices + 1, 0);
  for (const EdgeKey& k : topo.edges) ++c.offsets[k[0] + 1], ++c.offsets[k[1] + 1];
  std::partial_sum(c.offsets.begin(), c.offsets.end(), c.offsets.begin());
  c.indices.resize(c.offsets.back());
  std::vector<Index> fill(c.offsets.begin(), c.offsets.end() - 1);
  for (Index e = 0; e < topo.num_edges(); ++e)
    for (Index v : topo.edges[e]) c.indices[fill[v]++] = e;
  return c;
}

Index find_root(std::vector<Index>& parent, Index x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

Vec3 unit_normal(const TriangleMesh& mesh, Index t) { return triangle_normal_area2(mesh, t).normalized(); }

Vec3 quarter_turn(const Vec3& x, const Vec3& n, int r) {
  switch (mod4(r)) {
    case 1: return n.cross(x);
    case 2: return -x;
    case 3: return -n.cross(x);
    default: return x;
  }
}

Vec3 combed_direction(const Surface& surface, const CrossField& field, const CutGraph& cut, Index t) {
  const Vec3 n = unit_normal(surface.mesh, t);
  return quarter_turn(field_direction(field, n, t), n, cut.comb[t]);
}

CutGraph cut_to_disk(const Surface& surface, const CrossField& field) {
  const TriangleMesh& mesh = surface.mesh;
  const MeshTopology& topo = surface.topology;
  const Index F = mesh.num_triangles(), V = mesh.num_vertices(), E = topo.num_edges();
  if (static_cast<Index>(field.direction.size()) != F)
    throw std::invalid_argument("cut_to_disk: the cross field does not belong to this surface");

  CutGraph cut;
  std::vector<Vec3> normal(F), dir(F);
  for (Index t = 0; t < F; ++t) {
    normal[t] = unit_normal(mesh, t);
    dir[t] = field_direction(field, normal[t], t);
  }

  // --- Matching and holonomy -----------------------------------------------
  // Crossing e from t0 to t1 turns counter-clockwise about the head q of e as
  // t0 runs along it (t0 = (p, q, s)), clockwise about its tail p.
  cut.matching.assign(E, 0);
  std::vector<int> holonomy(V, 0);
  std::vector<std::uint8_t> on_boundary(V, 0);
  for (Index e = 0; e < E; ++e) {
    const auto [t0, t1] = topo.edge_triangles[e];
    if (t1 == kInvalid) {
      on_boundary[topo.edges[e][0]] = on_boundary[topo.edges[e][1]] = 1;
      continue;
    }
    const Vec3 a = (mesh.positions[topo.edges[e][1]] - mesh.positions[topo.edges[e][0]]).normalized();
    const Vec3 d0 = transport(dir[t0], a, normal[t0], normal[t1]);
    const double angle = std::atan2(normal[t1].dot(d0.cross(dir[t1])), d0.dot(dir[t1]));
    const int r = mod4(static_cast<int>(std::lround(angle / (M_PI / 2))));
    cut.matching[e] = static_cast<std::int8_t>(r);
    int k = 0;
    while (topo.triangle_edges[t0][k] != e) ++k;
    holonomy[mesh.triangles[t0][(k + 1) % 3]] += r;
    holonomy[mesh.triangles[t0][k]] -= r;
  }

  std::vector<std::uint8_t> cut_end(V, 0);
  for (const Singularity& s : field.singularities)
    if (s.vertex >= 0 && s.vertex < V && !on_boundary[s.vertex]) cut_end[s.vertex] = 1;
  for (Index v = 0; v < V; ++v)
    if (!on_boundary[v] && mod4(holonomy[v]) != 0) cut_end[v] = 1;
  for (Index v = 0; v < V; ++v)
    if (cut_end[v]) cut.cut_ends.push_back(v);

  // --- Dual spanning tree, combing ---------------------------------------------
  // Breadth first, so that the tree is shallow and the cut short.
  cut.comb.assign(F, 0);
  cut.component.assign(F, kInvalid);
  std::vector<std::uint8_t> in_tree(E, 0);
  std::vector<Index> queue;
  queue.reserve(F);
  for (Index seed = 0; seed < F; ++seed) {
    if (cut.component[seed] != kInvalid) continue;
    const Index c = static_cast<Index>(cut.tree_root.size());
    cut.tree_root.push_back(seed);
    cut.component[seed] = c;
    queue.clear();
    queue.push_back(seed);
    for (size_t head = 0; head < queue.size(); ++head) {
      const Index t = queue[head];
      for (Index e : topo.triangle_edges[t]) {
        const auto [t0, t1] = topo.edge_triangles[e];
        if (t1 == kInvalid) continue;
        const Index u = t0 == t ? t1 : t0;
        if (cut.component[u] != kInvalid) continue;
        // The combed field of u must be the combed field of t carried over.
        const int r = t0 == t ? cut.matching[e] : -cut.matching[e];
        cut.comb[u] = static_cast<std::int8_t>(mod4(cut.comb[t] - r));
        cut.component[u] = c;
        in_tree[e] = 1;
        queue.push_back(u);
      }
    }
  }

  // --- Cut: the complement of the tree, pruned ---------------------------------
  const Csr incident = vertex_edges(topo, V);
  cut.on_cut.assign(E, 0);
  std::vector<Index> degree(V, 0);
  for (Index e = 0; e < E; ++e)
    if (topo.edge_triangles[e][1] != kInvalid && !in_tree[e]) {
      cut.on_cut[e] = 1;
      ++degree[topo.edges[e][0]], ++degree[topo.edges[e][1]];
    }
  // Boundary vertices are never pruned: a branch between two boundaries (or
  // around a handle) may be needed, and a superfluous branch ending on the
  // boundary is pruned from its other, interior end.
  auto prunable = [&](Index v) { return degree[v] == 1 && !on_boundary[v] && !cut_end[v]; };
  std::vector<Index> stack;
  for (Index v = 0; v < V; ++v)
    if (prunable(v)) stack.push_back(v);
  while (!stack.empty()) {
    const Index v = stack.back();
    stack.pop_back();
    if (!prunable(v)) continue;
    for (const Index* it = incident.begin(v); it != incident.end(v); ++it) {
      if (!cut.on_cut[*it]) continue;
      cut.on_cut[*it] = 0;
      const Index w = topo.edges[*it][0] == v ? topo.edges[*it][1] : topo.edges[*it][0];
      --degree[v], --degree[w];
      if (prunable(w)) stack.push_back(w);
      break;
    }
  }

  // Combed matchings. Off the cut they vanish: on tree edges by construction,
  // on pruned edges because each was the last edge around a vertex of zero
  // holonomy whose other edges already had combed matching 0.
  cut.combed_matching.assign(E, 0);
  for (Index e = 0; e < E; ++e) {
    const auto [t0, t1] = topo.edge_triangles[e];
    if (t1 == kInvalid) continue;
    const int r = mod4(cut.matching[e] + cut.comb[t1] - cut.comb[t0]);
    if (!cut.on_cut[e] && r != 0)
      throw std::logic_error("cut_to_disk: an edge off the cut has a non-zero combed matching");
    cut.combed_matching[e] = static_cast<std::int8_t>(r);
  }

  // --- Wedges --------------------------------------------------------------
  // Union of corners across edges off the cut: the two triangles of such an
  // edge share both its vertices' copies.
  std::vector<Index> parent(3 * static_cast<size_t>(F));
  std::iota(parent.begin(), parent.end(), 0);
  auto corner_of = [&](Index t, Index v) {
    const Tri& f = mesh.triangles[t];
    return 3 * t + (f[0] == v ? 0 : f[1] == v ? 1 : 2);
  };
  for (Index e = 0; e < E; ++e) {
    const auto [t0, t1] = topo.edge_triangles[e];
    if (t1 == kInvalid || cut.on_cut[e]) continue;
    for (Index v : topo.edges[e]) {
      const Index a = find_root(parent, corner_of(t0, v)), b = find_root(parent, corner_of(t1, v));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  cut.wedge.assign(parent.size(), kInvalid);
  for (Index c = 0; c < static_cast<Index>(parent.size()); ++c) {
    const Index root = find_root(parent, c);
    if (cut.wedge[root] == kInvalid) {
      cut.wedge[root] = static_cast<Index>(cut.wedge_vertex.size());
      cut.wedge_vertex.push_back(mesh.triangles[root / 3][root % 3]);
    }
    cut.wedge[c] = cut.wedge[root];
  }
  return cut;
}

}  // namespace stripweave
