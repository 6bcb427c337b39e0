// Outlier vertices: points of a mesh far from all the rest (a corrupt
// coordinate, a stray vertex of an export).
//
// remove_outlier_vertices(mesh) -> the number of outlier vertices removed;
//   their triangles are removed too (counted in *triangles_removed).
// A vertex is an outlier when every edge it has is longer than kOutlierReach
// times R, the radius about the per-axis median that holds 95% of the
// vertices. WHY: a vertex sampling the surface has a neighbour nearby (the
// tip of a cone fanned from its base is the only sampled point with no near
// neighbour, and then only for a cone over 100 times longer than the rest is
// wide); a stray vertex spans the model with every edge. Left in, one vertex
// at 1e7 drives the remesher past 4 GB, one at 1e3 makes 2.3 times the
// target triangles, and the bounding box (the model's scale) is its.
// The median and R ignore up to 5% of strays.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

namespace stripweave {

constexpr double kOutlierReach = 100.0;

Index remove_outlier_vertices(TriangleMesh& mesh, Index* triangles_removed);

}  // namespace stripweave
