// What the symmetric-mesh constructions (symmetric_surface.cpp,
// rotation_surface.cpp) share.
//
// rebuild_surface_structure(out, is_feature, end): what a Surface derives
//   from its mesh, rebuilt once its positions, triangles and per-vertex data
//   are set: topology, components, boundary loops, genus, edge classes and
//   feature curves. is_feature(edge) for each interior edge of the new
//   topology; end[v]: a vertex where a feature curve of the original ended
//   (kept as a chain break).
// carry_source(out, s): the fields that do not depend on the mesh (the
//   similarity, the source B-rep and mesh, counts, warnings, timings).
// mean_edge_length(s): of the solver mesh (normalized units).
// feature_curve_ends(s): per vertex, whether an open feature curve ends there.
// clip_triangle(tri, d, corner, crossing, emit): the part of a triangle where
//   d >= 0 (d per vertex: the signed distance to a cutting plane), as a fan:
//   corner(v) gives the new vertex of a corner kept, crossing(a, b) that of
//   the point where edge ab crosses the plane, emit(a, b, c) takes each
//   triangle of the fan. Nothing of a triangle with no corner above the plane.
#pragma once

#include "stripweave/surface/surface.h"

#include <functional>
#include <vector>

namespace stripweave {

void rebuild_surface_structure(Surface& out, const std::function<bool(Index edge)>& is_feature,
                               const std::vector<bool>& end);
void carry_source(Surface& out, const Surface& s);
double mean_edge_length(const Surface& s);
std::vector<bool> feature_curve_ends(const Surface& s);

template <class Corner, class Crossing, class Emit>
void clip_triangle(const Tri& tri, const std::vector<double>& d, Corner corner, Crossing crossing, Emit emit) {
  bool positive = false, negative = false;
  for (Index v : tri) positive |= d[v] > 0, negative |= d[v] < 0;
  if (!positive) return;
  std::vector<Index> poly;
  for (int i = 0; i < 3; ++i) {
    const Index a = tri[i], b = tri[(i + 1) % 3];
    if (d[a] >= 0) poly.push_back(corner(a));
    if (negative && ((d[a] > 0 && d[b] < 0) || (d[a] < 0 && d[b] > 0))) poly.push_back(crossing(a, b));
  }
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) emit(poly[0], poly[i], poly[i + 1]);
}

}  // namespace stripweave
