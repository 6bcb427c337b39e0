// Primal patches: the refined mesh cut along the primal edges (paper §7).
//
// Each piece should hold exactly one loop crossing, whose four arc-ends its
// four sides are dual to. The piece's boundary is read on the cut-open mesh
// (wedges along the primal edges), so a vertex that several of its corners
// share (the single vertex of a torus layout is all four corners of its one
// patch) is told apart by side. Following the boundary counter-clockwise
// (the piece on the left), maximal runs along one primal edge in one
// direction are its sides, and the primal vertex where a run starts is a
// corner. Corner angles are measured between the sides' chords to a point a
// fifth of the shorter side away (which sees past what zig-zag is left of
// a mesh-edge path), projected into the patch's tangent plane there.
#include "stripweave/layout/primalization.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace stripweave {

namespace {

// The point at arc length `s` along the polyline of refined vertices.
Vec3 point_along(const std::vector<Vec3>& positions, const std::vector<Index>& path, bool backwards, double s) {
  const size_t n = path.size();
  auto at = [&](size_t i) { return positions[path[backwards ? n - 1 - i : i]]; };
  for (size_t i = 0; i + 1 < n; ++i) {
    const double len = (at(i + 1) - at(i)).norm();
    if (s <= len && len > 0) return at(i) + (s / len) * (at(i + 1) - at(i));
    s -= len;
  }
  return at(n - 1);
}

}  // namespace

void cut_primal_patches(const PrimalContext& ctx, QuadLayout& L) {
  const LoopArrangement& A = ctx.arrangement;
  const TriangleMesh& m = A.mesh;
  const MeshTopology& rt = A.topology;
  const Index nt = m.num_triangles(), ne = rt.num_edges();

  // Which primal edge each refined edge carries, and where along it.
  std::vector<Index> edge_primal(ne, kInvalid), edge_position(ne, kInvalid);
  for (size_t p = 0; p < L.edges.size(); ++p) {
    const std::vector<Index>& path = L.edges[p].path;
    for (size_t i = 0; i + 1 < path.size(); ++i) {
      const Index e = rt.find_edge(path[i], path[i + 1]);
      if (edge_primal[e] != kInvalid && edge_primal[e] != static_cast<Index>(p)) {
        L.problems.push_back("primal edges " + std::to_string(edge_primal[e]) + " and " + std::to_string(p) +
                             " share a stretch");
        continue;
      }
      if (edge_primal[e] == static_cast<Index>(p)) {
        L.problems.push_back("primal edge " + std::to_string(p) + " runs over itself");
        continue;
      }
      edge_primal[e] = static_cast<Index>(p);
      edge_position[e] = static_cast<Index>(i);
    }
  }
  auto is_cut = [&](Index e) { return edge_primal[e] != kInvalid || rt.is_boundary_edge(e); };
  L.patch_wedges = cut_wedges(m, rt, [&](Index e) { return edge_primal[e] != kInvalid; });
  const Wedges& W = L.patch_wedges;

  // Pieces: triangles joined across uncut edges.
  std::vector<Index> piece;
  triangle_components(rt, nt, piece, is_cut);
  // A piece is a patch through the crossing it holds.
  std::map<Index, Index> piece_patch;
  for (size_t k = 0; k < A.nodes.size(); ++k) {
    const ArrangementNode& node = A.nodes[k];
    if (!node.crossing()) continue;
    const Index v = node.vertex;
    if (rt.vertex_triangles.size(v) == 0) continue;
    const Index at = piece[*rt.vertex_triangles.begin(v)];
    if (piece_patch.count(at)) {
      L.problems.push_back("a patch holds more than one crossing (crossing at refined vertex " + std::to_string(v) + ")");
      continue;
    }
    piece_patch[at] = static_cast<Index>(L.patches.size());
    PrimalPatch patch;
    patch.node = static_cast<Index>(k);
    L.patches.push_back(patch);
  }
  L.triangle_patch.assign(nt, kInvalid);
  Index orphans = 0;
  for (Index t = 0; t < nt; ++t) {
    const auto it = piece_patch.find(piece[t]);
    if (it == piece_patch.end()) {
      ++orphans;
      continue;
    }
    L.triangle_patch[t] = it->second;
    PrimalPatch& patch = L.patches[it->second];
    patch.triangles.push_back(t);
    const Tri& f = m.triangles[t];
    const std::vector<Vec3>& P = L.positions;
    patch.area += 0.5 * (P[f[1]] - P[f[0]]).cross(P[f[2]] - P[f[0]]).norm();
  }
  if (orphans > 0)
    L.problems.push_back(std::to_string(orphans) + " refined triangles lie in no patch (a piece without a crossing)");
  // Creases inside a patch: crease edges with the same patch on both sides.
  for (Index e = 0; e < rt.num_edges(); ++e) {
    if (!ctx.edge_feature[e] || rt.is_boundary_edge(e)) continue;
    const Index a = L.triangle_patch[rt.edge_triangles[e][0]], b = L.triangle_patch[rt.edge_triangles[e][1]];
    if (a != kInvalid && a == b)
      L.patches[a].crease_length += (L.positions[rt.edges[e][0]] - L.positions[rt.edges[e][1]]).norm();
  }

  // Each patch's boundary: half-edge (t, i) runs from corner i to i + 1 of t
  // with t on its left; the next starts at the wedge where it ends.
  for (size_t p = 0; p < L.patches.size(); ++p) {
    PrimalPatch& patch = L.patches[p];
    std::map<Index, std::pair<Index, int>> leaving;  // wedge -> boundary half-edge starting there
    bool pinched = false;
    for (Index t : patch.triangles) {
      for (int i = 0; i < 3; ++i) {
        if (!is_cut(rt.triangle_edges[t][i])) continue;
        pinched |= !leaving.emplace(W.of(t, i), std::pair<Index, int>(t, i)).second;
      }
    }
    if (leaving.empty() || pinched) {
      L.problems.push_back("patch " + std::to_string(p) + " is not a disc");
      continue;
    }
    // Walk the cycle from the start of a side.
    struct Step {
      Index edge;      // primal edge, kInvalid on open boundary no primal edge covers
      bool backwards;  // against the primal edge's path
      Index wedge;     // where the half-edge starts
      Index vertex;
    };
    std::vector<Step> cycle;
    const auto first = leaving.begin()->second;
    std::pair<Index, int> h = first;
    do {
      const auto [t, i] = h;
      const Index a = m.triangles[t][i], e = rt.triangle_edges[t][i];
      const Index pe = edge_primal[e];
      const bool backwards = pe != kInvalid && L.edges[pe].path[edge_position[e]] != a;
      cycle.push_back({pe, backwards, W.of(t, i), a});
      const auto next = leaving.find(W.of(t, (i + 1) % 3));
      if (next == leaving.end() || cycle.size() > leaving.size()) break;
      h = next->second;
    } while (h != first);
    if (cycle.size() != leaving.size()) {
      L.problems.push_back("patch " + std::to_string(p) + " has more than one boundary cycle");
      continue;
    }
    auto same_side = [](const Step& a, const Step& b) { return a.edge == b.edge && a.backwards == b.backwards; };
    const size_t n = cycle.size();
    size_t start = 0;
    while (start < n && same_side(cycle[start], cycle[(start + n - 1) % n])) ++start;
    if (start == n) start = 0;  // one side all around
    std::vector<Step> runs;
    for (size_t k = 0; k < n; ++k) {
      const Step& s = cycle[(start + k) % n];
      if (k == 0 || !same_side(s, runs.back())) runs.push_back(s);
    }
    bool quad = runs.size() == 4;
    for (const Step& r : runs) quad &= r.edge != kInvalid;
    if (!quad) {
      L.problems.push_back("patch " + std::to_string(p) + " has " + std::to_string(runs.size()) +
                           " sides, not 4 along primal edges");
      continue;
    }
    for (int k = 0; k < 4; ++k) {
      const PrimalEdge& e = L.edges[runs[k].edge];
      patch.edges[k] = runs[k].edge;
      patch.reversed[k] = runs[k].backwards;
      patch.corners[k] = runs[k].backwards ? e.v1 : e.v0;
      patch.corner_wedges[k] = runs[k].wedge;
      if (L.vertices[patch.corners[k]].refined_vertex != runs[k].vertex) {
        L.problems.push_back("patch " + std::to_string(p) + ": side " + std::to_string(k) +
                             " does not start at its primal vertex");
        quad = false;
      }
    }
    patch.quad = quad;
    if (!quad) continue;
    // The patch's own normal at each corner (its triangles there), for the
    // tangent plane the angle is measured in: the chords of curved sides
    // leave it, and at a crease the other patches' normals do not apply.
    std::array<Vec3, 4> normal;
    normal.fill(Vec3::Zero());
    for (Index t : patch.triangles) {
      const Tri& f = m.triangles[t];
      const std::vector<Vec3>& P = L.positions;
      const Vec3 n = (P[f[1]] - P[f[0]]).cross(P[f[2]] - P[f[0]]);
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 4; ++k)
          if (W.of(t, i) == patch.corner_wedges[k]) normal[k] += n;
    }
    for (int k = 0; k < 4; ++k) {
      const PrimalEdge& out = L.edges[patch.edges[k]];
      const PrimalEdge& in = L.edges[patch.edges[(k + 3) % 4]];
      const double reach = 0.2 * std::min(out.length, in.length);
      const Vec3 corner = L.positions[L.vertices[patch.corners[k]].refined_vertex];
      // The outgoing side from its start; the incoming side from its end.
      Vec3 a = point_along(L.positions, out.path, patch.reversed[k], reach) - corner;
      Vec3 b = point_along(L.positions, in.path, !patch.reversed[(k + 3) % 4], reach) - corner;
      if (normal[k].norm() > 0) {
        const Vec3 n = normal[k].normalized();
        a -= a.dot(n) * n;
        b -= b.dot(n) * n;
      }
      patch.corner_angle[k] = std::atan2(a.cross(b).norm(), a.dot(b));
    }
  }
}

}  // namespace stripweave
