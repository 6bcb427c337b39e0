#include "stripweave/symmetry/rotation_surface.h"

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/core/error.h"
#include "stripweave/symmetry/surface_rebuild.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

namespace stripweave {

namespace {

// A triangle soup being cut into the sector M0. on[0] / on[1]: the vertex
// lies on the near / far half-plane (at angle 0 / 2 pi / n), both for a
// vertex on the axis.
struct Sector {
  std::vector<Vec3> positions;
  std::vector<Tri> triangles;
  std::vector<std::uint8_t> on[2];
};

struct Frame {
  Vec3 centre, axis, start, end;  // start, end: unit, across the axis, at angles 0 and 2 pi / n
  double snap;
};

// Keep the side of the plane through the axis with normal `normal` (the
// points p with normal . (p - centre) >= 0), cutting the triangles across
// it; a vertex on the plane (snapped onto it, or a cut point) gets the flag
// on[side] when it lies on the half-plane towards `half` (the other half of
// the plane is cut away by the second cut, or is the axis).
Sector cut(const Sector& in, const Frame& f, const Vec3& normal, const Vec3& half, int side) {
  const Index nv = static_cast<Index>(in.positions.size());
  std::vector<double> d(nv);
  for (Index v = 0; v < nv; ++v) {
    d[v] = normal.dot(in.positions[v] - f.centre);
    if (std::abs(d[v]) < f.snap) d[v] = 0;
  }
  Sector out;
  std::vector<Index> id(nv, kInvalid);
  const auto add = [&](const Vec3& p, bool on_plane, std::uint8_t on0, std::uint8_t on1) {
    const Vec3 q = on_plane ? Vec3(p - normal * normal.dot(p - f.centre)) : p;
    out.positions.push_back(q);
    const bool on_half = on_plane && half.dot(q - f.centre) > -f.snap;
    out.on[0].push_back(on0 || (side == 0 && on_half));
    out.on[1].push_back(on1 || (side == 1 && on_half));
    return static_cast<Index>(out.positions.size() - 1);
  };
  const auto vertex = [&](Index v) {
    if (id[v] == kInvalid) id[v] = add(in.positions[v], d[v] == 0, in.on[0][v], in.on[1][v]);
    return id[v];
  };
  std::unordered_map<std::uint64_t, Index> crossing;
  const auto cross = [&](Index a, Index b) {
    const std::uint64_t key = pack_edge(edge_key(a, b));
    const auto it = crossing.find(key);
    if (it != crossing.end()) return it->second;
    const double t = d[a] / (d[a] - d[b]);
    const Index v = add((1 - t) * in.positions[a] + t * in.positions[b], true, in.on[0][a] && in.on[0][b],
                        in.on[1][a] && in.on[1][b]);
    crossing.emplace(key, v);
    return v;
  };
  for (const Tri& tri : in.triangles)
    clip_triangle(tri, d, vertex, cross, [&](Index a, Index b, Index c) { out.triangles.push_back({a, b, c}); });
  return out;
}

// The seam edges on one half-plane: edges of one triangle (the sector's
// boundary) with both ends on it; per edge its ends and its triangle.
struct SeamEdge {
  Index a, b, triangle;
};

// Per edge of the sector (packed key), how many of its triangles use it: 1
// on its boundary (the seams and the part's open boundary).
std::unordered_map<std::uint64_t, int> edge_uses(const Sector& m) {
  std::unordered_map<std::uint64_t, int> uses;
  for (const Tri& t : m.triangles)
    for (int i = 0; i < 3; ++i) ++uses[pack_edge(edge_key(t[i], t[(i + 1) % 3]))];
  return uses;
}

std::vector<SeamEdge> seam_edges(const Sector& m, int side) {
  std::unordered_map<std::uint64_t, int> uses = edge_uses(m);
  std::vector<SeamEdge> out;
  for (Index k = 0; k < static_cast<Index>(m.triangles.size()); ++k) {
    const Tri& t = m.triangles[k];
    for (int i = 0; i < 3; ++i) {
      const Index a = t[i], b = t[(i + 1) % 3];
      const bool axial = m.on[0][a] && m.on[1][a] && m.on[0][b] && m.on[1][b];
      if (m.on[side][a] && m.on[side][b] && !axial && uses[pack_edge(edge_key(a, b))] == 1)
        out.push_back({a, b, k});
    }
  }
  return out;
}

// Split the sector's boundary edge e at p, a new vertex with the given
// half-plane flags: e's triangle keeps the half at e.a, the half at e.b
// becomes a new last triangle (both in the triangle's orientation).
Index split(Sector& m, const SeamEdge& e, const Vec3& p, bool on0, bool on1) {
  const Index x = static_cast<Index>(m.positions.size());
  m.positions.push_back(p);
  m.on[0].push_back(on0);
  m.on[1].push_back(on1);
  Tri& t = m.triangles[e.triangle];
  int i = 0;
  while (!((t[i] == e.a && t[(i + 1) % 3] == e.b) || (t[i] == e.b && t[(i + 1) % 3] == e.a))) ++i;
  const Index first = t[i], second = t[(i + 1) % 3], opposite = t[(i + 2) % 3];
  const Tri keep = first == e.a ? Tri{first, x, opposite} : Tri{x, second, opposite};
  const Tri added = first == e.a ? Tri{x, second, opposite} : Tri{first, x, opposite};
  t = keep;
  m.triangles.push_back(added);
  return x;
}

// Put point p (on half-plane `side`) into that seam: the seam vertex within
// the snap distance if there is one not `taken` (matched already), else a
// new vertex splitting the nearest seam edge (and its triangle, keeping its
// orientation). Returns the vertex, kInvalid when p is off the seam.
Index put_on_seam(Sector& m, std::vector<SeamEdge>& seam, int side, const Vec3& p, double snap,
                  const std::unordered_map<Index, Index>& taken) {
  Index nearest = kInvalid;
  double best = std::numeric_limits<double>::infinity();
  for (const SeamEdge& e : seam)
    for (Index v : {e.a, e.b}) {
      const double dv = (m.positions[v] - p).norm();
      if (dv < best && !taken.count(v)) best = dv, nearest = v;
    }
  if (nearest != kInvalid && best < snap) return nearest;
  std::size_t which = seam.size();
  best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < seam.size(); ++i) {
    const Vec3 a = m.positions[seam[i].a], ab = m.positions[seam[i].b] - a;
    const double t = std::clamp(ab.dot(p - a) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
    const double de = (a + t * ab - p).norm();
    if (de < best) best = de, which = i;
  }
  if (which == seam.size() || best > 2 * snap) return kInvalid;  // p is off this seam
  const SeamEdge e = seam[which];
  const Index x = split(m, e, p, side == 0, side == 1);
  // The two halves, in the triangle's order (split keeps e.a's half in e.triangle).
  seam[which] = {e.a, x, e.triangle};
  seam.push_back({x, e.b, static_cast<Index>(m.triangles.size() - 1)});
  return x;
}

// Match the two seams of the sector: each far-seam vertex with the near-seam
// vertex its preimage under psi lands on, and each near-seam vertex with the
// far-seam vertex its image lands on. Returns per vertex its partner on the
// far seam (near-seam vertices) or kInvalid; the far vertices are moved to
// the exact images of their partners.
std::vector<Index> match_seams(Sector& m, const Symmetry& rot, double snap) {
  std::vector<SeamEdge> seam[2] = {seam_edges(m, 0), seam_edges(m, 1)};
  const auto vertices_of = [&](int side) {
    std::vector<Index> out;
    for (const SeamEdge& e : seam[side]) out.push_back(e.a), out.push_back(e.b);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  };
  const std::vector<Index> near = vertices_of(0), far = vertices_of(1);
  std::unordered_map<Index, Index> partner, matched;  // near vertex -> far vertex, and back
  const auto pair = [&](Index w, Index q) {
    if (w == kInvalid || q == kInvalid)
      throw InputError("the part is not rotation-symmetric at its seam: a sector's two sides differ");
    partner[w] = q;
    matched[q] = w;
  };
  for (Index q : far) pair(put_on_seam(m, seam[0], 0, rot.inverse_point(m.positions[q]), snap, partner), q);
  for (Index w : near)
    if (!partner.count(w)) pair(w, put_on_seam(m, seam[1], 1, rot.map_point(m.positions[w]), snap, matched));
  std::vector<Index> out(m.positions.size(), kInvalid);
  for (const auto& [w, q] : partner) {
    out[w] = q;
    m.positions[q] = rot.map_point(m.positions[w]);
  }
  return out;
}

Index find(std::vector<Index>& parent, Index x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// Two vertices on the axis joined by an edge (a cut point the second cut
// made there beside a vertex snapped onto it) would make an edge every copy
// shares: the shorter than 2 snap of such edges are collapsed, their
// triangles dropped, and the unused vertices removed.
void merge_axis_vertices(Sector& m, double snap) {
  const Index nv = static_cast<Index>(m.positions.size());
  std::vector<Index> to(nv);
  std::iota(to.begin(), to.end(), 0);
  const auto axial = [&](Index v) { return m.on[0][v] && m.on[1][v]; };
  for (const Tri& t : m.triangles)
    for (int i = 0; i < 3; ++i) {
      const Index a = find(to, t[i]), b = find(to, t[(i + 1) % 3]);
      if (a != b && axial(a) && axial(b) && (m.positions[a] - m.positions[b]).norm() < 2 * snap) to[b] = a;
    }
  Sector out;
  std::vector<Index> id(nv, kInvalid);
  for (const Tri& t : m.triangles) {
    const Tri u{find(to, t[0]), find(to, t[1]), find(to, t[2])};
    if (u[0] == u[1] || u[1] == u[2] || u[0] == u[2]) continue;
    Tri w;
    for (int i = 0; i < 3; ++i) {
      if (id[u[i]] == kInvalid) {
        id[u[i]] = static_cast<Index>(out.positions.size());
        out.positions.push_back(m.positions[u[i]]);
        out.on[0].push_back(m.on[0][u[i]]);
        out.on[1].push_back(m.on[1][u[i]]);
      }
      w[i] = id[u[i]];
    }
    out.triangles.push_back(w);
  }
  m = std::move(out);
}

// The sector M0 of the surface, its seams matched (match_seams).
Sector sector_of(const Surface& s, const Symmetry& rot, const Frame& f, std::vector<Index>& partner) {
  Sector m;
  m.positions = s.mesh.positions;
  m.triangles = s.mesh.triangles;
  m.on[0].assign(m.positions.size(), 0);
  m.on[1].assign(m.positions.size(), 0);
  // The sector is the intersection of two half-spaces (its angle is at most
  // pi): the side of the start plane towards the end, then the side of the
  // end plane towards the start. For order 2 both planes are one.
  m = cut(m, f, f.axis.cross(f.start), f.start, 0);
  m = cut(m, f, -f.axis.cross(f.end), f.end, 1);
  if (m.triangles.empty()) throw InputError("the rotation's sector holds no surface");
  const auto radial = [&](const Vec3& p) {
    const Vec3 r = p - f.centre;
    return Vec3(r - f.axis * f.axis.dot(r));
  };
  for (Index v = 0; v < static_cast<Index>(m.positions.size()); ++v) {
    if (radial(m.positions[v]).norm() < f.snap) {  // on the axis: its own image, on both seams
      m.positions[v] -= radial(m.positions[v]);
      m.on[0][v] = m.on[1][v] = 1;
    }
  }
  // Where the surface crosses the axis inside a triangle, the boundary runs
  // from one seam to the other across it (order 2 has one cutting plane, so
  // no second cut makes the point there): a vertex on the axis, on both.
  std::unordered_map<std::uint64_t, int> uses = edge_uses(m);
  const Index triangles = static_cast<Index>(m.triangles.size());
  for (Index k = 0; k < triangles; ++k)
    for (int i = 0; i < 3; ++i) {
      const Index a = m.triangles[k][i], b = m.triangles[k][(i + 1) % 3];
      if (uses[pack_edge(edge_key(a, b))] != 1 || m.on[0][a] == m.on[0][b] || m.on[1][a] == m.on[1][b] ||
          !(m.on[0][a] || m.on[1][a]) || !(m.on[0][b] || m.on[1][b]))
        continue;  // not from the near seam's side to the far seam's, off the axis
      const double ra = radial(m.positions[a]).norm(), rb = radial(m.positions[b]).norm();
      const Vec3 p = m.positions[a] + ra / (ra + rb) * (m.positions[b] - m.positions[a]);
      split(m, {a, b, k}, p - radial(p), true, true);
      break;  // the triangle changed: its other edges are not on the seams
    }
  merge_axis_vertices(m, f.snap);
  partner = match_seams(m, rot, f.snap);
  return m;
}

// The original surface's data at a point (its nearest point's triangle,
// barycentric): normal, curvatures and principal directions (sign-aligned
// to the first corner's before blending: they are line fields).
struct PointData {
  Vec3 normal, d_min;
  double k_min, k_max;
};

PointData data_at(const Surface& s, const SurfacePoint3& p) {
  const Tri& t = s.mesh.triangles[p.triangle];
  PointData out{Vec3::Zero(), Vec3::Zero(), 0, 0};
  const Vec3 reference = s.d_min[t[0]];
  for (int i = 0; i < 3; ++i) {
    const double w = p.barycentric[i];
    out.normal += w * s.normal[t[i]];
    out.d_min += w * (s.d_min[t[i]].dot(reference) < 0 ? Vec3(-s.d_min[t[i]]) : s.d_min[t[i]]);
    out.k_min += w * s.k_min[t[i]];
    out.k_max += w * s.k_max[t[i]];
  }
  out.normal.normalize();
  out.d_min = (out.d_min - out.normal * out.normal.dot(out.d_min)).normalized();
  return out;
}

// Whether the segment a-b lies on a feature edge of the original: its ends
// within `tolerance` of a feature edge of the original triangle nearest its
// middle, and its middle within a quarter of that. (A tolerance, not the
// exact edge: a seam vertex is the image of one on the other seam, and lies
// off the original by up to the symmetry's error; the middle's tighter one
// keeps out an edge of a sliver the cut left beside a crease, nearly along
// it, which made a one-edge spur.)
bool on_feature(const Surface& s, const SurfaceLocator& locate, const Vec3& a, const Vec3& b, double tolerance) {
  const Vec3 mid = 0.5 * (a + b);
  const Tri& t = s.mesh.triangles[locate.closest(mid).triangle];
  for (int i = 0; i < 3; ++i) {
    const Index e = s.topology.find_edge(t[i], t[(i + 1) % 3]);
    if (e == kInvalid || s.edge_class[e] != EdgeClass::Feature) continue;
    const Vec3 u = s.mesh.positions[t[i]], uv = s.mesh.positions[t[(i + 1) % 3]] - u;
    const auto off = [&](const Vec3& p) {
      const double x = std::clamp(uv.dot(p - u) / std::max(uv.squaredNorm(), 1e-300), 0.0, 1.0);
      return (u + x * uv - p).norm();
    };
    if (off(a) < tolerance && off(b) < tolerance && off(mid) < 0.25 * tolerance) return true;
  }
  return false;
}

// The direction across the axis where the sector starts: of 16 evenly spaced
// in the first sector, the one whose half-plane passes farthest from the
// surface's vertices (least snapped, fewest slivers) and crosses the fewest
// feature edges. A CAD part's revolved faces have their B-rep seam at angle
// 0 of their own frame, where the tessellation is least regular; a cut
// along it snapped a row of vertices and left one-edge creases as spurs.
Vec3 quiet_start(const Surface& s, const Symmetry& rot, const Frame& f) {
  const Vec3 any = std::abs(f.axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 x = (any - f.axis * f.axis.dot(any)).normalized(), y = f.axis.cross(x);
  const double sector = 2 * M_PI / rot.order;
  Vec3 best = x;
  double best_cost = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 16; ++k) {
    const double angle = sector * k / 16.0;
    const Vec3 start = std::cos(angle) * x + std::sin(angle) * y, normal = f.axis.cross(start);
    const auto d = [&](Index v) { return normal.dot(s.mesh.positions[v] - f.centre); };
    const auto on_half = [&](Index v) { return start.dot(s.mesh.positions[v] - f.centre) > 0; };
    double cost = 0;
    for (Index v = 0; v < s.mesh.num_vertices(); ++v)
      if (on_half(v) && std::abs(d(v)) < f.snap) cost += 1;
    for (Index e = 0; e < s.topology.num_edges(); ++e) {
      const EdgeKey& k2 = s.topology.edges[e];
      if (s.edge_class[e] == EdgeClass::Feature && on_half(k2[0]) && (d(k2[0]) > 0) != (d(k2[1]) > 0)) cost += 1;
    }
    if (cost < best_cost) best_cost = cost, best = start;
  }
  return best;
}


// The n copies of the sector (copy k = psi^k of it), welded: copy k's far
// seam is copy k+1's near seam, and the axis is one for all. Per out vertex
// `local` gives its copy and sector vertex (k * sector vertices + v); per
// copy and sector vertex, `index` its out vertex.
struct Copies {
  TriangleMesh mesh;
  std::vector<Index> local, index;
};

Copies weld_copies(const Sector& m, const std::vector<Index>& partner, const Symmetry& rot) {
  const Index n = rot.order, ns = static_cast<Index>(m.positions.size());
  std::vector<Index> parent(n * ns);
  std::iota(parent.begin(), parent.end(), 0);
  const auto unite = [&](Index a, Index b) { parent[find(parent, a)] = find(parent, b); };
  for (Index k = 0; k < n; ++k)
    for (Index v = 0; v < ns; ++v) {
      if (m.on[0][v] && m.on[1][v]) unite(k * ns + v, v);
      else if (partner[v] != kInvalid) unite(k * ns + partner[v], ((k + 1) % n) * ns + v);
    }
  Copies c;
  c.index.assign(n * ns, kInvalid);
  for (Index g = 0; g < n * ns; ++g) {
    const Index r = find(parent, g);
    if (c.index[r] == kInvalid) {
      c.index[r] = c.mesh.num_vertices();
      c.mesh.positions.push_back(rot.map_point(m.positions[g % ns], static_cast<int>(g / ns)));
      c.local.push_back(g);
    }
    c.index[g] = c.index[r];
  }
  for (Index k = 0; k < n; ++k)
    for (const Tri& t : m.triangles)
      c.mesh.triangles.push_back({c.index[k * ns + t[0]], c.index[k * ns + t[1]], c.index[k * ns + t[2]]});
  return c;
}

// Per-vertex data of the welded copies from the original at the sector's
// vertices (`at`: their nearest original points), turned with each copy;
// each triangle's source B-rep face is that of the original triangle nearest
// its centroid.
void fill_data(Surface& out, const Surface& s, const Copies& c, const std::vector<SurfacePoint3>& at,
               const SurfaceLocator& locate, const Symmetry& rot) {
  const Index ns = static_cast<Index>(at.size()), nv = out.mesh.num_vertices();
  std::vector<PointData> data(ns);
  for (Index v = 0; v < ns; ++v) data[v] = data_at(s, at[v]);
  out.normal.resize(nv), out.k_min.resize(nv), out.k_max.resize(nv), out.d_min.resize(nv), out.d_max.resize(nv);
  for (Index v = 0; v < nv; ++v) {
    const int k = static_cast<int>(c.local[v] / ns);
    const PointData& d = data[c.local[v] % ns];
    out.normal[v] = rot.map_direction(d.normal, k);
    out.d_min[v] = rot.map_direction(d.d_min, k);
    out.d_max[v] = out.normal[v].cross(out.d_min[v]);
    out.k_min[v] = d.k_min;
    out.k_max[v] = d.k_max;
  }
  if (s.source_face.empty()) return;
  out.source_face.resize(out.mesh.num_triangles());
  for (Index t = 0; t < out.mesh.num_triangles(); ++t) {
    const Tri& tri = out.mesh.triangles[t];
    const Vec3 centroid = (out.mesh.positions[tri[0]] + out.mesh.positions[tri[1]] + out.mesh.positions[tri[2]]) / 3.0;
    out.source_face[t] = s.source_face[locate.closest(centroid).triangle];
  }
}

// Feature edges and curve ends of the welded copies: the sector's edges on
// an original feature edge (on_feature), in every copy; a vertex at an
// original curve end stays a chain break.
void fill_features(Surface& out, const Surface& s, const Sector& m, const Copies& c,
                   const std::vector<SurfacePoint3>& at, const SurfaceLocator& locate, int order, double tolerance) {
  const Index ns = static_cast<Index>(m.positions.size()), nv = out.mesh.num_vertices();
  std::unordered_map<std::uint64_t, bool> sector_feature;
  for (const Tri& t : m.triangles)
    for (int i = 0; i < 3; ++i) {
      const Index a = t[i], b = t[(i + 1) % 3];
      sector_feature.emplace(pack_edge(edge_key(a, b)), on_feature(s, locate, m.positions[a], m.positions[b], tolerance));
    }
  const std::vector<bool> was_end = feature_curve_ends(s);
  std::vector<bool> end(nv, false);
  for (Index v = 0; v < nv; ++v) {
    const SurfacePoint3& p = at[c.local[v] % ns];
    const Tri& t = s.mesh.triangles[p.triangle];
    for (int i = 0; i < 3; ++i) end[v] = end[v] || (p.barycentric[i] > 1 - 1e-9 && was_end[t[i]]);
  }
  std::unordered_map<std::uint64_t, bool> feature;  // per out edge (packed key)
  for (Index k = 0; k < order; ++k)
    for (const Tri& t : m.triangles)
      for (int i = 0; i < 3; ++i) {
        const Index a = t[i], b = t[(i + 1) % 3];
        bool& x = feature[pack_edge(edge_key(c.index[k * ns + a], c.index[k * ns + b]))];
        x = x || sector_feature[pack_edge(edge_key(a, b))];
      }
  rebuild_surface_structure(out, [&](Index e) { return feature[pack_edge(out.topology.edges[e])]; }, end);
}

}  // namespace

Surface rotation_symmetric_surface(const Surface& s, const Symmetry& rot, const std::optional<Vec3>& sector_start) {
  if (rot.kind != SymmetryKind::Rotation || rot.order < 2) throw InputError("not a rotation");
  Frame f;
  f.centre = rot.point;
  f.axis = rot.direction.normalized();
  f.snap = 0.1 * mean_edge_length(s);
  const Vec3 across = sector_start ? Vec3(*sector_start - f.axis * f.axis.dot(*sector_start)) : Vec3::Zero();
  if (sector_start && !(across.norm() > 1e-9)) throw InputError("a sector's start must point across the axis");
  f.start = sector_start ? Vec3(across.normalized()) : quiet_start(s, rot, f);
  f.end = rot.map_direction(f.start);
  std::vector<Index> partner;
  const Sector m = sector_of(s, rot, f, partner);
  Copies c = weld_copies(m, partner, rot);
  Surface out;
  out.mesh = std::move(c.mesh);
  const SurfaceLocator locate(s.mesh);
  std::vector<SurfacePoint3> at(m.positions.size());
  for (std::size_t v = 0; v < at.size(); ++v) at[v] = locate.closest(m.positions[v]);
  fill_data(out, s, c, at, locate, rot);
  carry_source(out, s);
  fill_features(out, s, m, c, at, locate, rot.order, f.snap);
  if (out.genus != s.genus || out.components != s.components || out.boundary_loops.size() != s.boundary_loops.size())
    throw InputError("the part is not rotation-symmetric enough for one sector to stand for the others (genus " +
                     std::to_string(out.genus) + " against " + std::to_string(s.genus) + ", " +
                     std::to_string(out.boundary_loops.size()) + " boundary loops against " +
                     std::to_string(s.boundary_loops.size()) + ")");
  return out;
}

}  // namespace stripweave
