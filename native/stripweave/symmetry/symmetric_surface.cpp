#include "stripweave/symmetry/symmetric_surface.h"

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/core/error.h"
#include "stripweave/surface/feature_curves.h"
#include "stripweave/symmetry/rotation_surface.h"
#include "stripweave/symmetry/surface_rebuild.h"

#include <unordered_map>

namespace stripweave {

namespace {

// Where a vertex of M0 comes from: an original vertex (b == kInvalid) or the
// point at t along the original edge a -> b.
struct Origin {
  Index a = kInvalid, b = kInvalid;
  double t = 0;
};

struct Half {
  std::vector<Vec3> positions;
  std::vector<Origin> origin;
  std::vector<bool> on_plane;
  std::vector<Tri> triangles;
  std::vector<Index> source_triangle;  // per triangle of M0
};

Half cut_half(const Surface& s, const Symmetry& m) {
  const double snap = 0.1 * mean_edge_length(s);
  const Index nv = s.mesh.num_vertices();
  std::vector<double> d(nv);
  Half h;
  std::vector<Index> id(nv, kInvalid);
  for (Index v = 0; v < nv; ++v) {
    d[v] = m.direction.dot(s.mesh.positions[v] - m.point);
    if (std::abs(d[v]) < snap) d[v] = 0;
  }
  const auto vertex = [&](Index v) {
    if (id[v] == kInvalid) {
      id[v] = static_cast<Index>(h.positions.size());
      const Vec3 p = s.mesh.positions[v];
      h.positions.push_back(d[v] == 0 ? Vec3(p - m.direction * m.direction.dot(p - m.point)) : p);
      h.origin.push_back({v, kInvalid, 0});
      h.on_plane.push_back(d[v] == 0);
    }
    return id[v];
  };
  std::unordered_map<std::uint64_t, Index> cut;
  const auto crossing = [&](Index a, Index b) {
    const std::uint64_t key = pack_edge(edge_key(a, b));
    auto it = cut.find(key);
    if (it != cut.end()) return it->second;
    const double t = d[a] / (d[a] - d[b]);
    Vec3 p = (1 - t) * s.mesh.positions[a] + t * s.mesh.positions[b];
    p -= m.direction * m.direction.dot(p - m.point);
    const Index v = static_cast<Index>(h.positions.size());
    h.positions.push_back(p);
    h.origin.push_back({a, b, t});
    h.on_plane.push_back(true);
    cut.emplace(key, v);
    return v;
  };
  for (Index t = 0; t < s.mesh.num_triangles(); ++t)
    clip_triangle(s.mesh.triangles[t], d, vertex, crossing, [&](Index a, Index b, Index c) {
      h.triangles.push_back({a, b, c});
      h.source_triangle.push_back(t);
    });
  return h;
}

template <typename T>
T at_origin(const std::vector<T>& data, const Origin& o) {
  return o.b == kInvalid ? data[o.a] : T((1 - o.t) * data[o.a] + o.t * data[o.b]);
}

// The class of M0's edge (u, v) from the original edges it lies on.
EdgeClass class_of(const Surface& s, const Origin& u, const Origin& v) {
  Index a = u.a, b = v.a;
  if (u.b != kInvalid && v.b != kInvalid) return EdgeClass::Regular;  // across a triangle
  if (u.b != kInvalid) {
    if (v.a != u.a && v.a != u.b) return EdgeClass::Regular;
    a = u.a, b = u.b;
  } else if (v.b != kInvalid) {
    if (u.a != v.a && u.a != v.b) return EdgeClass::Regular;
    a = v.a, b = v.b;
  }
  const Index e = s.topology.find_edge(a, b);
  return e == kInvalid || s.edge_class[e] == EdgeClass::Boundary ? EdgeClass::Regular : s.edge_class[e];
}

}  // namespace

Surface symmetric_surface(const Surface& s, const Symmetry& m) {
  if (m.kind == SymmetryKind::Rotation) return rotation_symmetric_surface(s, m);
  const Half h = cut_half(s, m);
  const Index n0 = static_cast<Index>(h.positions.size());
  if (h.triangles.empty() || h.triangles.size() == s.mesh.triangles.size())
    throw InputError("the symmetry plane does not cut the surface into two parts");
  Surface out;
  carry_source(out, s);
  // Vertices: M0's, then the mirror of each that is off the plane.
  std::vector<Index> mirror(n0);
  out.mesh.positions = h.positions;
  for (Index v = 0; v < n0; ++v) {
    if (h.on_plane[v]) {
      mirror[v] = v;
    } else {
      mirror[v] = out.mesh.num_vertices();
      out.mesh.positions.push_back(m.map_point(h.positions[v]));
    }
  }
  const Index nv = out.mesh.num_vertices();
  out.normal.resize(nv);
  out.k_min.resize(nv);
  out.k_max.resize(nv);
  out.d_min.resize(nv);
  out.d_max.resize(nv);
  for (Index v = 0; v < n0; ++v) {
    const Origin& o = h.origin[v];
    const Vec3 n = at_origin(s.normal, o).normalized();
    Vec3 dmin = at_origin(s.d_min, o);
    dmin = (dmin - n * n.dot(dmin)).normalized();
    out.normal[v] = n;
    out.k_min[v] = at_origin(s.k_min, o);
    out.k_max[v] = at_origin(s.k_max, o);
    out.d_min[v] = dmin;
    out.d_max[v] = n.cross(dmin);
    if (mirror[v] != v) {
      const Index w = mirror[v];
      out.normal[w] = m.map_direction(out.normal[v]);
      out.k_min[w] = out.k_min[v];
      out.k_max[w] = out.k_max[v];
      out.d_min[w] = m.map_direction(out.d_min[v]);
      out.d_max[w] = m.map_direction(out.d_max[v]);
    }
  }
  // Triangles: M0's, then their mirror images (reversed: a reflection flips orientation).
  out.mesh.triangles = h.triangles;
  for (const Tri& t : h.triangles) out.mesh.triangles.push_back({mirror[t[0]], mirror[t[2]], mirror[t[1]]});
  const SurfaceLocator original(s.mesh);
  out.source_face.resize(out.mesh.num_triangles(), kInvalid);
  if (!s.source_face.empty()) {
    for (std::size_t t = 0; t < h.triangles.size(); ++t) out.source_face[t] = s.source_face[h.source_triangle[t]];
    for (std::size_t t = h.triangles.size(); t < out.mesh.triangles.size(); ++t) {
      const Tri& tri = out.mesh.triangles[t];
      const Vec3 c = (out.mesh.positions[tri[0]] + out.mesh.positions[tri[1]] + out.mesh.positions[tri[2]]) / 3.0;
      out.source_face[t] = s.source_face[original.closest(c).triangle];
    }
  }
  // Edge classes from M0's edges (a mirrored edge takes its original's class).
  std::vector<Index> source(nv, kInvalid);  // per vertex, its M0 vertex
  for (Index v = 0; v < n0; ++v) source[v] = v, source[mirror[v]] = v;
  std::vector<bool> end(nv, false);
  const std::vector<bool> was_end = feature_curve_ends(s);
  for (Index v = 0; v < nv; ++v) {
    const Origin& o = h.origin[source[v]];
    end[v] = o.b == kInvalid && was_end[o.a];
  }
  rebuild_surface_structure(out, [&](Index e) {
    const Index u = source[out.topology.edges[e][0]], v = source[out.topology.edges[e][1]];
    return class_of(s, h.origin[u], h.origin[v]) == EdgeClass::Feature;
  }, end);
  return out;
}

}  // namespace stripweave
