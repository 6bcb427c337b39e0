#include "stripweave/surface/sanitize_mesh.h"

#include "stripweave/core/error.h"
#include "stripweave/surface/mesh_topology.h"
#include "stripweave/surface/outlier_vertices.h"
#include "stripweave/surface/weld_vertices.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <limits>
#include <unordered_set>

namespace stripweave {

namespace {

std::string plural(Index n, const char* one, const char* many) {
  std::ostringstream s;
  s << n << " " << (n == 1 ? one : many);
  return s.str();
}

void check_input(const TriangleMesh& raw) {
  if (raw.triangles.empty()) throw InputError("the mesh holds no triangles");
  Index bad = 0, first = kInvalid;
  for (Index v = 0; v < raw.num_vertices(); ++v)
    if (!raw.positions[v].allFinite() && bad++ == 0) first = v;
  if (bad > 0) {
    std::ostringstream msg;
    msg << "the mesh has " << plural(bad, "vertex", "vertices") << " with NaN or infinite coordinates (first: vertex "
        << first << ")";
    throw InputError(msg.str());
  }
  for (Index t = 0; t < raw.num_triangles(); ++t)
    for (Index v : raw.triangles[t])
      if (v < 0 || v >= raw.num_vertices()) {
        std::ostringstream msg;
        msg << "triangle " << t << " refers to vertex " << v << ", but the mesh has only " << raw.num_vertices()
            << " vertices";
        throw InputError(msg.str());
      }
}

// Triangles with a repeated vertex, and every later copy of a triangle (the
// same three vertices in any order), are removed; the first copy stays where
// it was. A hash of the sorted corners: a std::set of them took a second of a
// million-triangle load.
Index remove_repeated_and_duplicates(TriangleMesh& m, Index& duplicates) {
  Index repeated = 0;
  duplicates = 0;
  std::size_t capacity = 16;
  while (capacity < 2 * m.triangles.size()) capacity *= 2;
  const std::size_t mask = capacity - 1;
  std::vector<Index> slot(capacity, kInvalid);  // a kept triangle, or empty
  std::vector<Tri> kept;
  std::vector<std::array<Index, 3>> kept_key;
  kept.reserve(m.triangles.size());
  kept_key.reserve(m.triangles.size());
  for (const Tri& t : m.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++repeated;
      continue;
    }
    std::array<Index, 3> key = t;
    std::sort(key.begin(), key.end());
    std::uint64_t h = (static_cast<std::uint64_t>(key[0]) * 0x9e3779b97f4a7c15ULL) ^
                      (static_cast<std::uint64_t>(key[1]) * 0xc2b2ae3d27d4eb4fULL) ^
                      (static_cast<std::uint64_t>(key[2]) * 0x165667b19e3779f9ULL);
    std::size_t i = (h ^ (h >> 29)) & mask;
    while (slot[i] != kInvalid && kept_key[slot[i]] != key) i = (i + 1) & mask;
    if (slot[i] != kInvalid) {
      ++duplicates;
      continue;
    }
    slot[i] = static_cast<Index>(kept.size());
    kept.push_back(t);
    kept_key.push_back(key);
  }
  m.triangles.swap(kept);
  return repeated;
}

// A zero-area triangle (a, b, c) with c on its longest edge ab is removed by
// flipping ab in the pair (a,b,c),(b,a,d) into (c,a,d),(c,d,b): no hole opens.
// On a boundary edge the cap is simply dropped.
// The triangles on each edge, as (edge, triangle) pairs sorted by edge, then
// by triangle (the order they were met in): flat, where a hash map of vectors
// allocated one vector per edge of a million-triangle mesh.
class EdgeTriangles {
 public:
  explicit EdgeTriangles(const TriangleMesh& m) {
    pairs_.reserve(3 * m.triangles.size());
    for (Index t = 0; t < m.num_triangles(); ++t)
      for (int i = 0; i < 3; ++i) pairs_.push_back({pack_edge(edge_key(m.triangles[t][i], m.triangles[t][(i + 1) % 3])), t});
    std::sort(pairs_.begin(), pairs_.end());
  }
  // The triangles of edge k, [begin, end).
  std::pair<const std::pair<std::uint64_t, Index>*, const std::pair<std::uint64_t, Index>*> of(std::uint64_t k) const {
    auto lo = std::lower_bound(pairs_.begin(), pairs_.end(), std::make_pair(k, std::numeric_limits<Index>::min()));
    auto hi = lo;
    while (hi != pairs_.end() && hi->first == k) ++hi;
    return {pairs_.data() + (lo - pairs_.begin()), pairs_.data() + (hi - pairs_.begin())};
  }
  bool has(std::uint64_t k) const { return added_.count(k) || of(k).first != of(k).second; }
  void add(std::uint64_t k) { added_.insert(k); }

 private:
  std::vector<std::pair<std::uint64_t, Index>> pairs_;
  std::unordered_set<std::uint64_t> added_;  // edges a flip made in this pass
};

bool any_zero_area(const TriangleMesh& m, double eps) {
  for (Index t = 0; t < m.num_triangles(); ++t)
    if (!(triangle_normal_area2(m, t).norm() > eps)) return true;
  return false;
}

Index repair_zero_area(TriangleMesh& m) {
  const double diag = bounding_box(m.positions).diagonal();
  const double eps = 1e-14 * diag * diag;
  Index repaired = 0;
  for (int pass = 0; pass < 3; ++pass) {
    if (!any_zero_area(m, eps)) break;  // most meshes: no edge table at all
    EdgeTriangles by_edge(m);
    std::vector<bool> removed(m.triangles.size(), false), touched(m.triangles.size(), false);
    Index changed = 0;
    for (Index t = 0; t < m.num_triangles(); ++t) {
      if (touched[t] || triangle_normal_area2(m, t).norm() > eps) continue;
      const Tri f = m.triangles[t];
      int longest = 0;
      double best = -1;
      for (int i = 0; i < 3; ++i) {
        const double l = (m.positions[f[(i + 1) % 3]] - m.positions[f[i]]).squaredNorm();
        if (l > best) best = l, longest = i;
      }
      const Index a = f[longest], b = f[(longest + 1) % 3], c = f[(longest + 2) % 3];
      Index n = kInvalid;
      for (auto [it, end] = by_edge.of(pack_edge(edge_key(a, b))); it != end; ++it)
        if (it->second != t && !touched[it->second]) n = it->second;
      if (n == kInvalid) {  // a cap on the boundary: dropping it opens no hole
        removed[t] = touched[t] = true;
        ++changed;
        continue;
      }
      Index d = kInvalid;
      for (Index v : m.triangles[n])
        if (v != a && v != b) d = v;
      if (d == kInvalid || d == c || by_edge.has(pack_edge(edge_key(c, d)))) continue;  // would duplicate an edge
      m.triangles[t] = {c, a, d};
      m.triangles[n] = {c, d, b};
      touched[t] = touched[n] = true;  // adjacency is stale for these until the next pass
      by_edge.add(pack_edge(edge_key(c, d)));
      ++changed;
    }
    std::vector<Tri> kept;
    kept.reserve(m.triangles.size());
    for (Index t = 0; t < m.num_triangles(); ++t)
      if (!removed[t]) kept.push_back(m.triangles[t]);
    m.triangles.swap(kept);
    repaired += changed;
    if (changed == 0) break;
  }
  return repaired;
}

// Make the orientation consistent across every edge, component by component.
// Returns the number of flipped triangles; throws for a non-orientable surface.
Index orient_consistently(TriangleMesh& m, const MeshTopology& topo) {
  const Index nt = m.num_triangles();
  std::vector<int> state(nt, 0);  // 0 unvisited, 1 kept, -1 flipped
  Index flipped = 0;
  // Two triangles sharing edge (a,b) are consistent when they traverse it in
  // opposite directions.
  auto direction = [&](Index t, const EdgeKey& e) {
    const Tri& f = m.triangles[t];
    for (int i = 0; i < 3; ++i)
      if (f[i] == e[0] && f[(i + 1) % 3] == e[1]) return 1;
    return -1;
  };
  for (Index seed = 0; seed < nt; ++seed) {
    if (state[seed] != 0) continue;
    state[seed] = 1;
    std::vector<Index> stack{seed};
    while (!stack.empty()) {
      const Index t = stack.back();
      stack.pop_back();
      for (Index e : topo.triangle_edges[t]) {
        const Index n = topo.edge_triangles[e][0] == t ? topo.edge_triangles[e][1] : topo.edge_triangles[e][0];
        if (n == kInvalid) continue;
        const int want = -direction(t, topo.edges[e]) * state[t];  // n's direction times its state
        const int needed_state = want * direction(n, topo.edges[e]);
        if (state[n] == 0) {
          state[n] = needed_state;
          stack.push_back(n);
        } else if (state[n] != needed_state) {
          std::ostringstream msg;
          const Vec3& p = m.positions[topo.edges[e][0]];
          msg << "the surface is not orientable (like a Moebius strip) near (" << p.x() << ", " << p.y() << ", "
              << p.z() << ")";
          throw InputError(msg.str());
        }
      }
    }
  }
  for (Index t = 0; t < nt; ++t)
    if (state[t] < 0) {
      std::swap(m.triangles[t][1], m.triangles[t][2]);
      ++flipped;
    }
  return flipped;
}

Index drop_unreferenced(TriangleMesh& m) {
  std::vector<Index> remap(m.positions.size(), kInvalid);
  std::vector<Vec3> kept;
  for (Tri& t : m.triangles)
    for (Index& v : t) {
      if (remap[v] == kInvalid) {
        remap[v] = static_cast<Index>(kept.size());
        kept.push_back(m.positions[v]);
      }
      v = remap[v];
    }
  const Index dropped = m.num_vertices() - static_cast<Index>(kept.size());
  m.positions.swap(kept);
  return dropped;
}

}  // namespace

SanitizedMesh sanitize_mesh(const TriangleMesh& raw, double debris_fraction) {
  check_input(raw);
  SanitizedMesh out;
  auto& warn = out.warnings;
  TriangleMesh m = weld_coincident(raw);
  Index outlier_triangles = 0;
  const Index outliers = remove_outlier_vertices(m, &outlier_triangles);
  if (outliers) {
    std::ostringstream msg;
    msg << "removed " << plural(outliers, "outlier vertex", "outlier vertices") << " (every edge over " << kOutlierReach
        << " times the radius of the rest) and " << plural(outlier_triangles, "triangle", "triangles");
    warn.push_back(msg.str());
  }
  // Before the repairs, so no tolerance below is scaled by a point no triangle uses (one at
  // 1e7 made every triangle of a 10 mm box "zero-area").
  Index unreferenced = drop_unreferenced(m) - outliers;

  Index duplicates = 0;
  if (Index n = remove_repeated_and_duplicates(m, duplicates))
    warn.push_back("removed " + plural(n, "degenerate triangle", "degenerate triangles") + " with a repeated vertex");
  if (duplicates) warn.push_back("removed " + plural(duplicates, "duplicate triangle", "duplicate triangles"));
  if (Index n = repair_zero_area(m))
    warn.push_back("repaired " + plural(n, "zero-area triangle", "zero-area triangles") + " by edge flips");
  if (m.triangles.empty()) throw InputError("the mesh holds no triangles with area");

  MeshTopology topo = MeshTopology::build(m);  // throws on non-manifold edges
  if (Index n = static_cast<Index>(split_pinched_vertices(m, topo).size())) {
    warn.push_back("split " + plural(n, "non-manifold (pinched) vertex", "non-manifold (pinched) vertices"));
    topo = MeshTopology::build(m);
  }
  if (Index n = orient_consistently(m, topo))
    warn.push_back("flipped " + plural(n, "inconsistently oriented triangle", "inconsistently oriented triangles"));

  // Components: orient closed ones outward, drop debris.
  std::vector<Index> comp;
  const Index nc = triangle_components(topo, m.num_triangles(), comp);
  std::vector<double> area(nc, 0.0), volume(nc, 0.0);
  std::vector<bool> closed(nc, true);
  for (Index t = 0; t < m.num_triangles(); ++t) {
    const Tri& f = m.triangles[t];
    area[comp[t]] += 0.5 * triangle_normal_area2(m, t).norm();
    volume[comp[t]] += m.positions[f[0]].dot(m.positions[f[1]].cross(m.positions[f[2]])) / 6.0;
  }
  for (Index e = 0; e < topo.num_edges(); ++e)
    if (topo.is_boundary_edge(e)) closed[comp[topo.edge_triangles[e][0]]] = false;
  double total_area = 0;
  for (double a : area) total_area += a;
  Index debris = 0, inward = 0;
  std::vector<Tri> kept;
  std::vector<bool> keep(nc);
  for (Index c = 0; c < nc; ++c) {
    keep[c] = area[c] >= debris_fraction * total_area;
    if (!keep[c]) ++debris;
    if (keep[c] && closed[c] && volume[c] < 0) ++inward;
  }
  for (Index t = 0; t < m.num_triangles(); ++t) {
    const Index c = comp[t];
    if (!keep[c]) continue;
    Tri f = m.triangles[t];
    if (closed[c] && volume[c] < 0) std::swap(f[1], f[2]);
    kept.push_back(f);
  }
  m.triangles.swap(kept);
  if (debris) warn.push_back("dropped " + plural(debris, "tiny disconnected piece", "tiny disconnected pieces"));
  if (inward) warn.push_back("turned " + plural(inward, "inside-out component", "inside-out components") + " outward");
  if (nc - debris > 1)
    warn.push_back("the surface has " + std::to_string(nc - debris) + " separate components; each is kept");
  unreferenced += drop_unreferenced(m);
  if (unreferenced)
    warn.push_back("dropped " + plural(unreferenced, "unreferenced vertex", "unreferenced vertices"));
  out.mesh = std::move(m);
  return out;
}

}  // namespace stripweave
