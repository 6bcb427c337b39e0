// SurfaceReport: the figures `stripweave info` prints (keys of design.md).
#pragma once

#include "stripweave/surface/surface.h"

namespace stripweave {

struct SurfaceReport {
  Index vertices = 0, triangles = 0, components = 0;
  int genus = 0;
  Index boundary_loops = 0, feature_curves = 0, feature_edges = 0, brep_faces = 0;
  double bbox_diagonal = 0;  // model units
  std::vector<std::string> warnings;
};

SurfaceReport surface_report(const Surface& surface);

// Genus from the Euler characteristic, summed over components:
// V - E + F = sum_i (2 - 2 g_i - b_i).
int genus_from_euler(Index vertices, Index edges, Index faces, Index components, Index boundary_loops);

}  // namespace stripweave
