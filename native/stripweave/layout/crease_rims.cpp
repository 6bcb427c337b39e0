// The rims of a part and their loop crossings (see the header).
#include "stripweave/layout/crease_rims.h"

#include <algorithm>
#include <array>

namespace stripweave {

namespace {

// One closed walk along a rim: vertices[i] and vertices[i + 1] (wrapping)
// are joined by edges[i].
struct RimWalk {
  std::vector<Index> vertices, edges;
};

struct Rims {
  const LoopArrangement& A;
  // Per refined vertex: how many crease edges meet there, the first two of
  // them (a rim's vertices have exactly two), and whether it is on the open
  // boundary. Flat arrays: this runs in every assessment of the weave.
  std::vector<std::uint8_t> degree, on_boundary, seen;
  std::vector<std::array<Index, 2>> crease_edges;

  Rims(const LoopArrangement& a, const std::vector<std::uint8_t>& crease)
      : A(a), degree(a.mesh.num_vertices(), 0), on_boundary(a.mesh.num_vertices(), 0),
        seen(a.mesh.num_vertices(), 0), crease_edges(a.mesh.num_vertices(), {kInvalid, kInvalid}) {
    for (Index e = 0; e < A.topology.num_edges(); ++e) {
      if (crease[e])
        for (Index v : A.topology.edges[e]) {
          if (degree[v] < 2) crease_edges[v][degree[v]] = e;
          degree[v] = static_cast<std::uint8_t>(std::min(3, degree[v] + 1));
        }
      if (A.topology.is_boundary_edge(e))
        for (Index v : A.topology.edges[e]) on_boundary[v] = 1;
    }
  }

  bool plain(Index v) const { return degree[v] == 2 && !on_boundary[v]; }

  Index other(Index e, Index v) const {
    const EdgeKey& k = A.topology.edges[e];
    return k[0] == v ? k[1] : k[0];
  }

  // From v along its crease edge `e` while vertices are plain, marking them
  // seen. True if the walk came back to v (a rim); `walk` then holds it.
  bool walk_from(Index v, Index e, RimWalk& walk) {
    walk = {{v}, {}};
    for (Index at = v; true;) {
      walk.edges.push_back(e);
      at = other(e, at);
      if (at == v) return true;
      seen[at] = 1;
      if (!plain(at)) return false;
      walk.vertices.push_back(at);
      e = crease_edges[at][0] == e ? crease_edges[at][1] : crease_edges[at][0];
    }
  }

  // A loop crosses the rim at a vertex on a loop edge when neither of the
  // rim's edges there is one (a loop along the rim crosses nothing).
  bool crossed_at(Index v) const {
    if (A.degree[v] == 0) return false;
    for (Index e : crease_edges[v])
      if (A.on_loop(e)) return false;
    return true;
  }

  double length(Index a, Index b) const { return (A.mesh.positions[a] - A.mesh.positions[b]).norm(); }

  // The direction across the rim at walk position i, in the mean tangent
  // plane of its two sides.
  Vec3 across(const RimWalk& w, size_t i) const {
    const size_t n = w.vertices.size();
    const Vec3 tangent = A.mesh.positions[w.vertices[(i + 1) % n]] - A.mesh.positions[w.vertices[(i + n - 1) % n]];
    Vec3 normal = Vec3::Zero();
    for (Index t : A.topology.edge_triangles[w.edges[i]])
      if (t != kInvalid) normal += triangle_normal_area2(A.mesh, t).normalized();
    const Vec3 d = normal.cross(tangent);
    return d.norm() > 0 ? Vec3(d.normalized()) : Vec3::Zero();
  }

  // Walk position halfway (by length) along the longest stretch between
  // consecutive crossings (`at`: their positions, ascending), strictly
  // inside it; the whole rim from its first vertex when none crosses it.
  size_t seed_position(const RimWalk& w, const std::vector<size_t>& at) const {
    const size_t n = w.vertices.size();
    if (at.empty()) {
      return static_cast<size_t>(std::min_element(w.vertices.begin(), w.vertices.end()) - w.vertices.begin());
    }
    size_t best = n;  // n: no stretch has an inner vertex
    double longest = 0;
    for (size_t k = 0; k < at.size(); ++k) {
      const size_t from = at[k], to = k + 1 < at.size() ? at[k + 1] : at[0] + n;
      if (to - from < 2) continue;
      double total = 0;
      for (size_t i = from; i < to; ++i) total += length(w.vertices[i % n], w.vertices[(i + 1) % n]);
      if (total <= longest) continue;
      longest = total;
      double run = 0;
      size_t i = from;
      while (i + 2 < to && (run += length(w.vertices[i % n], w.vertices[(i + 1) % n])) < 0.5 * total) ++i;
      best = (i + 1) % n;
    }
    return best;
  }

  CreaseRim measure(const RimWalk& w, const std::vector<Index>& triangle_region) const {
    CreaseRim rim;
    std::vector<size_t> at;
    for (size_t i = 0; i < w.vertices.size(); ++i)
      if (crossed_at(w.vertices[i])) at.push_back(i);
    rim.crossings = static_cast<int>(at.size());
    rim.lack = std::max(0, kRimCrossings - rim.crossings);
    const size_t i = seed_position(w, at);
    if (i >= w.vertices.size()) return rim;
    rim.seed = w.vertices[i];
    rim.across = across(w, i);
    const Index t = A.topology.edge_triangles[w.edges[i]][0];
    rim.region = t == kInvalid ? kInvalid : triangle_region[t];
    return rim;
  }
};

}  // namespace

std::vector<CreaseRim> crease_rims(const LoopArrangement& A, const std::vector<std::uint8_t>& refined_crease,
                                   const std::vector<Index>& triangle_region) {
  Rims rims(A, refined_crease);
  std::vector<CreaseRim> out;
  RimWalk walk;
  for (Index v = 0; v < A.mesh.num_vertices(); ++v) {
    if (rims.seen[v] || !rims.plain(v)) continue;
    rims.seen[v] = 1;
    // Both ways from v: a chain that reaches a node is seen whole in one go.
    if (rims.walk_from(v, rims.crease_edges[v][0], walk)) {
      out.push_back(rims.measure(walk, triangle_region));
      continue;
    }
    rims.walk_from(v, rims.crease_edges[v][1], walk);
  }
  return out;
}

}  // namespace stripweave
