// angle_defects(mesh, topology) -> per vertex, its discrete Gaussian curvature
//   2 pi (pi on an open boundary, where it is the boundary's turn) minus the
//   angles of its corners. Each triangle's three angles are made to sum to pi
//   exactly, so the defects sum to 2 pi chi even over degenerate triangles.
//   Used by the cross field (turning of its frames), the regions' total
//   curvature and the primal vertices' corners.
#pragma once

#include "stripweave/surface/mesh_topology.h"

namespace stripweave {

std::vector<double> angle_defects(const TriangleMesh& mesh, const MeshTopology& topology);

}  // namespace stripweave
