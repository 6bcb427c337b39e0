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
#pragma once

#include "stripweave/surface/surface.h"

#include <functional>

namespace stripweave {

void rebuild_surface_structure(Surface& out, const std::function<bool(Index edge)>& is_feature,
                               const std::vector<bool>& end);
void carry_source(Surface& out, const Surface& s);
double mean_edge_length(const Surface& s);
std::vector<bool> feature_curve_ends(const Surface& s);

}  // namespace stripweave
