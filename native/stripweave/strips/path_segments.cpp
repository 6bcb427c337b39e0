// The pieces of an embedded loop inside each triangle it crosses (see the header).
//
// A path point is a mesh vertex or a point inside a mesh edge; the triangles
// that contain it are the vertex's fan or the edge's one or two triangles.
// Two consecutive points share at least one of them; they share two exactly
// when the step runs along a mesh edge, and then the triangle on the left of
// the travel direction is the one the step is said to cross, so that the
// choice is the same for every caller (the parameterization puts the loop's
// isocurve constraint into that triangle).
#include "stripweave/strips/path_segments.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace stripweave {

namespace {

// The triangles containing path point i, into `out`.
void containing_triangles(const Surface& s, const SurfacePath& path, Index i, std::vector<Index>& out) {
  out.clear();
  if (path.vertex[i] != kInvalid) {
    const Index v = path.vertex[i];
    out.assign(s.topology.vertex_triangles.begin(v), s.topology.vertex_triangles.end(v));
  } else if (path.edge[i] != kInvalid) {
    for (Index t : s.topology.edge_triangles[path.edge[i]])
      if (t != kInvalid) out.push_back(t);
  } else {
    throw std::invalid_argument("path_segments: path point " + std::to_string(i) +
                                " is neither on a mesh vertex nor on a mesh edge");
  }
}

Vec3 centroid(const Surface& s, Index t) {
  const Tri& f = s.mesh.triangles[t];
  const auto& P = s.mesh.positions;
  return (P[f[0]] + P[f[1]] + P[f[2]]) / 3.0;
}

// How far triangle t lies to the left of the step from a in direction d
// (positive on the left, seen from outside).
double leftness(const Surface& s, Index t, const Vec3& a, const Vec3& d) {
  const Vec3 n = triangle_normal_area2(s.mesh, t);
  return n.cross(d).dot(centroid(s, t) - a);
}

}  // namespace

std::vector<PathSegment> path_segments(const Surface& surface, const SurfacePath& path, bool closed) {
  const Index n = static_cast<Index>(path.points.size());
  if (path.vertex.size() != path.points.size() || path.edge.size() != path.points.size())
    throw std::invalid_argument("path_segments: a path needs a vertex and an edge entry per point");
  std::vector<PathSegment> segments;
  if (n < 2) return segments;
  segments.reserve(n);

  // A length below this (relative to the model's size 1) is a repeated point.
  constexpr double kRepeated = 1e-12;
  std::vector<Index> at_from, at_to;
  const Index steps = closed ? n : n - 1;
  for (Index i = 0; i < steps; ++i) {
    const Index j = (i + 1) % n;
    const Vec3 step = path.points[j] - path.points[i];
    const double length = step.norm();
    if (length <= kRepeated) continue;
    const Vec3 d = step / length;

    containing_triangles(surface, path, i, at_from);
    containing_triangles(surface, path, j, at_to);
    Index chosen = kInvalid;
    double best = -std::numeric_limits<double>::infinity();
    for (Index t : at_from) {
      if (std::find(at_to.begin(), at_to.end(), t) == at_to.end()) continue;
      // One common triangle: it. Two (along an edge): the one on the left.
      const double left = leftness(surface, t, path.points[i], d);
      if (chosen == kInvalid || left > best) chosen = t, best = left;
    }
    if (chosen == kInvalid)
      throw std::invalid_argument("path_segments: path points " + std::to_string(i) + " and " + std::to_string(j) +
                                  " share no triangle");
    segments.push_back({chosen, i, j, d});
  }
  return segments;
}

Vec3 barycentric_in(const Surface& surface, const SurfacePath& path, Index i, Index t) {
  const Tri& f = surface.mesh.triangles[t];
  Vec3 b = Vec3::Zero();
  auto corner = [&](Index v) {
    for (int k = 0; k < 3; ++k)
      if (f[k] == v) return k;
    throw std::invalid_argument("barycentric_in: path point " + std::to_string(i) + " is not on triangle " +
                                std::to_string(t));
  };
  if (path.vertex[i] != kInvalid) {
    b[corner(path.vertex[i])] = 1;
  } else {
    const EdgeKey& e = surface.topology.edges[path.edge[i]];
    b[corner(e[0])] = 1 - path.t[i];
    b[corner(e[1])] = path.t[i];
  }
  return b;
}

}  // namespace stripweave
