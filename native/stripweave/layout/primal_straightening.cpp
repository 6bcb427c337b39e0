// Straightening the primal edges. A shortest path over mesh edges zig-zags
// (up to about 8% longer than the geodesic on a well-shaped mesh, with
// tangents off by up to 30 degrees locally), which shows in the patch
// corners' angles and in the wires the surfacing stage fits. So the inner
// vertices of each primal edge are relaxed towards the midpoint of their
// neighbours along the edge, each kept on the surface inside its own star
// (the refined triangles around it, at their original positions: exactly
// the surface there) and only where none of its triangles would flip.
// Vertices on a loop (the edge's crossing), on a sharp feature, on the
// open boundary or where the user routed the edge through stay: there the
// edge follows what it must follow. The refined mesh's connectivity is unchanged, so the patches cut along the
// edges are the same sets of triangles, with moved vertices.
#include "stripweave/layout/primalization.h"

namespace stripweave {

namespace {

// The point of triangle (a, b, c) closest to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

constexpr int kIterations = 30;
constexpr double kStep = 0.5;

}  // namespace

void straighten_primal_edges(const PrimalContext& ctx, QuadLayout& L) {
  const LoopArrangement& A = ctx.arrangement;
  const TriangleMesh& m = A.mesh;
  const MeshTopology& rt = A.topology;
  L.positions = m.positions;

  std::vector<std::uint8_t> pinned(m.num_vertices(), 0);
  for (Index v = 0; v < m.num_vertices(); ++v) pinned[v] = ctx.vertex_on_loop[v] || ctx.vertex_on_boundary[v];
  for (Index e = 0; e < rt.num_edges(); ++e)
    if (ctx.edge_feature[e]) pinned[rt.edges[e][0]] = pinned[rt.edges[e][1]] = 1;
  for (const PrimalVertex& v : L.vertices)
    if (v.refined_vertex != kInvalid) pinned[v.refined_vertex] = 1;
  for (const PrimalEdge& e : L.edges)  // a hand route keeps its point
    if (e.through != kInvalid) pinned[e.through] = 1;

  auto flips = [&](Index x, const Vec3& q) {
    for (const Index* t = rt.vertex_triangles.begin(x); t != rt.vertex_triangles.end(x); ++t) {
      const Tri& f = m.triangles[*t];
      Vec3 p[3];
      for (int i = 0; i < 3; ++i) p[i] = f[i] == x ? q : L.positions[f[i]];
      const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
      const Vec3 n0 = triangle_normal_area2(m, *t);
      // Flipped, or squeezed to a sliver a tenth of its original area.
      if (n.dot(n0) <= 0.1 * n0.squaredNorm()) return true;
    }
    return false;
  };

  for (int it = 0; it < kIterations; ++it) {
    for (const PrimalEdge& e : L.edges) {
      for (size_t i = 1; i + 1 < e.path.size(); ++i) {
        const Index x = e.path[i];
        if (pinned[x]) continue;
        const Vec3 mid = 0.5 * (L.positions[e.path[i - 1]] + L.positions[e.path[i + 1]]);
        const Vec3 want = L.positions[x] + kStep * (mid - L.positions[x]);
        // Back onto the surface within x's star.
        Vec3 best = L.positions[x];
        double best_d = std::numeric_limits<double>::infinity();
        for (const Index* t = rt.vertex_triangles.begin(x); t != rt.vertex_triangles.end(x); ++t) {
          const Tri& f = m.triangles[*t];
          const Vec3 q = closest_on_triangle(want, m.positions[f[0]], m.positions[f[1]], m.positions[f[2]]);
          const double d = (q - want).squaredNorm();
          if (d < best_d) best_d = d, best = q;
        }
        if (!flips(x, best)) L.positions[x] = best;
      }
    }
  }
  for (PrimalEdge& e : L.edges) {
    e.length = 0;
    for (size_t i = 0; i + 1 < e.path.size(); ++i) e.length += (L.positions[e.path[i + 1]] - L.positions[e.path[i]]).norm();
  }
}

}  // namespace stripweave
