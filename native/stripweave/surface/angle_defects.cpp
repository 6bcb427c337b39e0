// Angle defects (see the header).
#include "stripweave/surface/angle_defects.h"

#include <cmath>

namespace stripweave {

std::vector<double> angle_defects(const TriangleMesh& mesh, const MeshTopology& topo) {
  const auto& P = mesh.positions;
  std::vector<double> defect(P.size(), 2 * M_PI);
  for (Index e = 0; e < topo.num_edges(); ++e)
    if (topo.is_boundary_edge(e)) defect[topo.edges[e][0]] = defect[topo.edges[e][1]] = M_PI;
  for (const Tri& f : mesh.triangles) {
    double angle[3], sum = 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = P[f[(k + 1) % 3]] - P[f[k]], b = P[f[(k + 2) % 3]] - P[f[k]];
      angle[k] = std::atan2(a.cross(b).norm(), a.dot(b));
      sum += angle[k];
    }
    for (int k = 0; k < 3; ++k) defect[f[k]] -= angle[k] + (M_PI - sum) / 3;
  }
  return defect;
}

}  // namespace stripweave
