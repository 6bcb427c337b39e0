// One triangle cut by the loops' chords (see the header).
#include "stripweave/layout/chord_split.h"

#include "stripweave/core/union_find.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace stripweave {

namespace {

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }


// The chords with the same two endpoints are one ("unique") chord; it keeps
// the input chords it stands for.
struct UniqueChord {
  Index a, b;  // boundary positions, a < b
  Vec2 p, d;   // start point and unit direction a -> b
  double length;
  std::vector<Index> inputs;
  std::vector<std::pair<double, Index>> hits;  // (parameter along the chord in [0, length], crossing)
  std::vector<Index> chain;                    // local vertex ids from a to b
};

// Two chords with distinct endpoints cross iff their endpoints interleave.
bool interleave(const UniqueChord& x, const UniqueChord& y) {
  return (x.a < y.a && y.a < x.b && x.b < y.b) || (y.a < x.a && x.a < y.b && y.b < x.b);
}

// A planar graph on local vertex ids whose rotation system is combinatorial.
// Every half-edge heads (along a side or a chord) towards a boundary
// position, its "far end" (and comes from the other end); rays from a point
// inside a convex polygon, or from a point on its boundary, meet the
// boundary in the order of their angles, so the counter-clockwise order of the half-edges leaving a vertex
// is the boundary order of their far ends (starting after the vertex itself
// when it is on the boundary). No rounded coordinate enters the rotation.
struct PlanarGraph {
  Index vertices = 0, boundary_size = 0;
  std::vector<std::array<Index, 2>> ends;
  std::vector<std::array<Index, 2>> far;  // far end of the half-edge leaving ends[0], and of the one leaving ends[1]
  std::unordered_map<std::uint64_t, Index> index;

  void add(Index u, Index v, Index far_from_u, Index far_from_v) {
    if (u == v) return;
    const std::uint64_t key = (static_cast<std::uint64_t>(std::min(u, v)) << 32) | static_cast<std::uint32_t>(std::max(u, v));
    if (!index.emplace(key, static_cast<Index>(ends.size())).second) return;  // a piece shared by several chords
    ends.push_back({u, v});
    far.push_back({far_from_u, far_from_v});
  }

  // Traces the faces. True iff the rotation system is planar (V - E + F = 2)
  // and the face outside the half-edge boundary[1] -> boundary[0] is the
  // boundary cycle (so the other faces tile the triangle); then `faces` gets
  // the inner faces as counter-clockwise vertex cycles.
  bool faces(std::vector<std::vector<Index>>& faces) const {
    const Index E = static_cast<Index>(ends.size()), H = 2 * E, nb = boundary_size;
    auto from = [&](Index h) { return ends[h >> 1][h & 1]; };
    auto to = [&](Index h) { return ends[h >> 1][1 - (h & 1)]; };
    // Pieces of two chords through one merged vertex may head for one
    // boundary point (they share that end); between them, the one whose
    // other end comes first after it is first (ccw).
    std::vector<std::pair<Index, Index>> key(H);
    for (Index h = 0; h < H; ++h) {
      const Index u = from(h), f = far[h >> 1][h & 1], o = far[h >> 1][1 - (h & 1)];
      key[h] = {u < nb ? (f - u + nb) % nb : f, (o - f + nb) % nb};
    }
    std::vector<Index> offset(vertices + 1, 0), order(H), slot(H);
    for (Index h = 0; h < H; ++h) ++offset[from(h) + 1];
    std::partial_sum(offset.begin(), offset.end(), offset.begin());
    {
      std::vector<Index> fill(offset.begin(), offset.end() - 1);
      for (Index h = 0; h < H; ++h) order[fill[from(h)]++] = h;
    }
    for (Index v = 0; v < vertices; ++v) {
      std::sort(order.begin() + offset[v], order.begin() + offset[v + 1],
                [&](Index x, Index y) { return key[x] < key[y]; });
      for (Index k = offset[v]; k < offset[v + 1]; ++k) slot[order[k]] = k;
    }
    // Keeping the face on the left: at v, leave by the edge just clockwise
    // of the one we arrived on.
    auto next = [&](Index h) {
      const Index v = to(h), twin = h ^ 1, deg = offset[v + 1] - offset[v];
      return order[offset[v] + (slot[twin] - offset[v] + deg - 1) % deg];
    };
    std::vector<Index> face(H, kInvalid);
    Index F = 0, outer = kInvalid, outer_length = 0;
    Index start_outer = kInvalid;  // the half-edge boundary[1] -> boundary[0]
    for (Index e = 0; e < E; ++e)
      if (ends[e][0] == 0 && ends[e][1] == 1) start_outer = 2 * e + 1;
      else if (ends[e][0] == 1 && ends[e][1] == 0) start_outer = 2 * e;
    if (start_outer == kInvalid) return false;
    std::vector<std::vector<Index>> cycles;
    for (Index h0 = 0; h0 < H; ++h0) {
      if (face[h0] != kInvalid) continue;
      std::vector<Index> cycle;
      Index h = h0;
      do {
        if (face[h] != kInvalid) return false;  // a rotation system always closes; defensive
        face[h] = F;
        cycle.push_back(from(h));
        h = next(h);
      } while (h != h0);
      if (face[start_outer] == F && outer == kInvalid) outer = F, outer_length = static_cast<Index>(cycle.size());
      cycles.push_back(std::move(cycle));
      ++F;
    }
    Index used = 0;
    for (Index v = 0; v < vertices; ++v) used += offset[v + 1] > offset[v];
    if (used - E + F != 2 || outer_length != nb) return false;
    faces.clear();
    for (Index f = 0; f < F; ++f)
      if (f != outer) faces.push_back(std::move(cycles[f]));
    return true;
  }
};

// Which crossings are one vertex, at a tolerance: per crossing its class.
// Crossings nearer than the tolerance along a chord merge; then, until
// nothing changes, a chord that leaves a merged vertex and comes back to it
// merges everything in between, and two crossing chords (interleaving ends)
// that would meet at two vertices have them merged: they must cross once.
// Chords that do not cross may touch any number of times.
std::vector<Index> merge_crossings(const std::vector<UniqueChord>& unique, Index crossings, double tolerance) {
  UnionFind merged(crossings);
  for (const UniqueChord& u : unique)
    for (size_t k = 1; k < u.hits.size(); ++k)
      if (u.hits[k].first - u.hits[k - 1].first < tolerance) merged.unite(u.hits[k].second, u.hits[k - 1].second);
  const Index nu = static_cast<Index>(unique.size());
  for (bool changed = true; changed;) {
    changed = false;
    for (const UniqueChord& u : unique) {
      std::unordered_map<Index, size_t> last;
      for (size_t k = 0; k < u.hits.size(); ++k) {
        auto [it, fresh] = last.emplace(merged.find(u.hits[k].second), k);
        if (!fresh && it->second + 1 != k)
          for (size_t m = it->second; m < k; ++m) changed |= merged.unite(u.hits[m].second, u.hits[k].second);
        it->second = k;
      }
    }
    for (Index i = 0; i < nu; ++i) {
      for (Index j = i + 1; j < nu; ++j) {
        if (!interleave(unique[i], unique[j])) continue;
        Index shared = kInvalid;
        for (const auto& hx : unique[i].hits)
          for (const auto& hy : unique[j].hits)
            if (merged.find(hx.second) == merged.find(hy.second)) {
              if (shared != kInvalid) changed |= merged.unite(shared, hx.second);
              shared = hx.second;
            }
      }
    }
  }
  std::vector<Index> root(crossings);
  for (Index x = 0; x < crossings; ++x) root[x] = merged.find(x);
  return root;
}

}  // namespace

bool on_common_side(const std::array<Index, 3>& corner_at, Index n, Index i, Index j) {
  auto on_side = [&](int k, Index x) {
    if (k < 2) return x >= corner_at[k] && x <= corner_at[k + 1];
    return x >= corner_at[2] || x == 0;
  };
  for (int k = 0; k < 3; ++k)
    if (on_side(k, i) && on_side(k, j)) return true;
  return false;
}

ChordSplit split_by_chords(const ChordSplitInput& in) {
  const Index nb = static_cast<Index>(in.boundary.size());
  const Index nc = static_cast<Index>(in.chords.size());
  ChordSplit out;

  // 1. Unique chords.
  std::vector<UniqueChord> unique;
  std::vector<Index> unique_of(nc);
  std::vector<bool> reversed(nc);
  {
    std::unordered_map<std::uint64_t, Index> seen;
    for (Index c = 0; c < nc; ++c) {
      Index a = in.chords[c][0], b = in.chords[c][1];
      if (a < 0 || b < 0 || a >= nb || b >= nb || on_common_side(in.corner_at, nb, a, b))
        throw std::logic_error("split_by_chords: a chord must join two boundary points on different sides");
      reversed[c] = a > b;
      if (a > b) std::swap(a, b);
      const std::uint64_t key = (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
      auto [it, fresh] = seen.emplace(key, static_cast<Index>(unique.size()));
      if (fresh) {
        UniqueChord u;
        u.a = a, u.b = b;
        u.p = in.boundary[a];
        const Vec2 d = in.boundary[b] - in.boundary[a];
        u.length = d.norm();
        u.d = d / u.length;
        unique.push_back(std::move(u));
      }
      unique_of[c] = it->second;
      unique[it->second].inputs.push_back(c);
    }
  }
  const Index nu = static_cast<Index>(unique.size());

  // 2. Crossings: exactly the pairs whose endpoints interleave. Only where
  //    along each chord is computed.
  std::vector<Vec2> crossing_pos;
  for (Index i = 0; i < nu; ++i) {
    for (Index j = i + 1; j < nu; ++j) {
      UniqueChord& x = unique[i];
      UniqueChord& y = unique[j];
      if (!interleave(x, y)) continue;
      const double denom = cross2(x.d, y.d);
      const Vec2 r = y.p - x.p;
      // They cross, so the lines are not parallel; clamping only guards rounding.
      double s = denom != 0 ? cross2(r, y.d) / denom : 0.5 * x.length;
      double u = denom != 0 ? cross2(r, x.d) / denom : 0.5 * y.length;
      s = std::clamp(s, 0.0, x.length);
      u = std::clamp(u, 0.0, y.length);
      const Index id = static_cast<Index>(crossing_pos.size());
      crossing_pos.push_back(0.5 * ((x.p + s * x.d) + (y.p + u * y.d)));
      x.hits.emplace_back(s, id);
      y.hits.emplace_back(u, id);
    }
  }
  const Index nx = static_cast<Index>(crossing_pos.size());
  for (UniqueChord& u : unique) std::sort(u.hits.begin(), u.hits.end());

  // 3. The planar graph of the pieces, for crossings merged at a tolerance
  //    (root per crossing), or as a star through one point (empty roots
  //    with star = true).
  auto position = [&](Index local) { return local < nb ? in.boundary[local] : out.points[local - nb]; };
  auto build = [&](const std::vector<Index>& root, bool star, PlanarGraph& g) {
    out.points.clear();
    out.crossing_chords.clear();
    if (star) {
      Vec2 c = Vec2::Zero();
      for (const Vec2& p : crossing_pos) c += p;
      const Vec2 centroid = (in.corners[0] + in.corners[1] + in.corners[2]) / 3.0;
      c = nx > 0 ? Vec2(c / nx) : centroid;
      for (int k = 0; k < 3; ++k) {  // strictly inside, else the centroid
        const Vec2 side = in.corners[(k + 1) % 3] - in.corners[k];
        if (cross2(side, c - in.corners[k]) <= 1e-9 * side.squaredNorm()) c = centroid;
      }
      out.points.push_back(c);
      out.crossing_chords.emplace_back();
      for (UniqueChord& u : unique) u.chain = {u.a, nb, u.b};
    } else {
      std::vector<Index> class_of(nx, kInvalid), members;
      for (Index x = 0; x < nx; ++x) {
        Index& c = class_of[root[x]];
        if (c == kInvalid) {
          c = static_cast<Index>(out.points.size());
          out.points.push_back(Vec2::Zero());
          out.crossing_chords.emplace_back();
          members.push_back(0);
        }
        class_of[x] = c;
        out.points[c] += crossing_pos[x];
        ++members[c];
      }
      for (size_t k = 0; k < out.points.size(); ++k) out.points[k] /= members[k];
      for (UniqueChord& u : unique) {
        u.chain.assign(1, u.a);
        for (const auto& [s, x] : u.hits)
          if (nb + class_of[x] != u.chain.back()) u.chain.push_back(nb + class_of[x]);
        u.chain.push_back(u.b);
      }
    }
    out.crossings = static_cast<Index>(out.points.size());
    g = PlanarGraph();
    g.vertices = nb + out.crossings;
    g.boundary_size = nb;
    for (Index i = 0; i < nb; ++i) g.add(i, (i + 1) % nb, (i + 1) % nb, i);
    for (const UniqueChord& u : unique) {
      for (size_t k = 0; k + 1 < u.chain.size(); ++k) {
        g.add(u.chain[k], u.chain[k + 1], u.b, u.a);
        if (u.chain[k + 1] >= nb) {
          auto& through = out.crossing_chords[u.chain[k + 1] - nb];
          through.insert(through.end(), u.inputs.begin(), u.inputs.end());
        }
      }
    }
  };

  // Merging at the tolerance makes a planar subdivision unless chords pass
  // within about the tolerance of several crossings at once in an order
  // rounding has scrambled; then merge more coarsely, and last use the star.
  PlanarGraph graph;
  std::vector<std::vector<Index>> faces;
  bool planar = false;
  for (double factor = 1; !planar && factor <= 1e3; factor *= 10) {
    build(merge_crossings(unique, nx, factor * in.tolerance), false, graph);
    planar = graph.faces(faces);
  }
  if (!planar) {
    out.star = true;
    build({}, true, graph);
    if (!graph.faces(faces))
      throw std::logic_error("split_by_chords: the chords of a triangle do not form a planar subdivision");
  }
  for (auto& through : out.crossing_chords) {
    std::sort(through.begin(), through.end());
    through.erase(std::unique(through.begin(), through.end()), through.end());
  }
  // 4. Fan each (convex) face from its best corner, or from its centroid.
  double scale2 = 0;
  for (int k = 0; k < 3; ++k) scale2 = std::max(scale2, (in.corners[(k + 1) % 3] - in.corners[k]).squaredNorm());
  const double flat = 1e-12 * scale2;  // twice the area below which a piece counts as flat
  auto area2 = [&](Index a, Index b, Index c) {
    return cross2(position(b) - position(a), position(c) - position(a));
  };
  for (const std::vector<Index>& f : faces) {
    const Index n = static_cast<Index>(f.size());
    if (n == 3) {
      out.triangles.push_back({f[0], f[1], f[2]});
      continue;
    }
    Index apex = 0;
    double best = -std::numeric_limits<double>::infinity();
    for (Index j = 0; j < n; ++j) {
      double worst = std::numeric_limits<double>::infinity();
      for (Index k = 1; k + 1 < n; ++k) worst = std::min(worst, area2(f[j], f[(j + k) % n], f[(j + k + 1) % n]));
      if (worst > best) best = worst, apex = j;
    }
    if (best <= flat) {
      Vec2 c = Vec2::Zero();
      for (Index v : f) c += position(v);
      out.points.push_back(c / n);
      const Index steiner = nb + static_cast<Index>(out.points.size()) - 1;
      double worst = std::numeric_limits<double>::infinity();
      for (Index k = 0; k < n; ++k) worst = std::min(worst, area2(steiner, f[k], f[(k + 1) % n]));
      if (worst > best) {
        for (Index k = 0; k < n; ++k) out.triangles.push_back({steiner, f[k], f[(k + 1) % n]});
        continue;
      }
      out.points.pop_back();
    }
    for (Index k = 1; k + 1 < n; ++k) out.triangles.push_back({f[apex], f[(apex + k) % n], f[(apex + k + 1) % n]});
  }

  // 5. Each input chord's vertices, in its own direction.
  out.chord_vertices.resize(nc);
  for (Index c = 0; c < nc; ++c) {
    out.chord_vertices[c] = unique[unique_of[c]].chain;
    if (reversed[c]) std::reverse(out.chord_vertices[c].begin(), out.chord_vertices[c].end());
  }
  return out;
}

}  // namespace stripweave
