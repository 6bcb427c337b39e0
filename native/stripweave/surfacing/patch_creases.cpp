#include "stripweave/surfacing/patch_creases.h"

#include "stripweave/surface/feature_curves.h"
#include "stripweave/surface/mesh_topology.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

PatchCreases patch_creases(const TriangleMesh& mesh, double crease_angle_deg) {
  PatchCreases result;
  if (mesh.num_triangles() == 0) return result;
  const MeshTopology topo = MeshTopology::build(mesh);
  const std::vector<bool> crease = dihedral_feature_edges(mesh, topo, crease_angle_deg);
  for (Index e = 0; e < topo.num_edges(); ++e) {
    const auto& et = topo.edge_triangles[e];
    if (et[1] == kInvalid) continue;
    const Vec3 n0 = triangle_normal_area2(mesh, et[0]), n1 = triangle_normal_area2(mesh, et[1]);
    if (n0.isZero() || n1.isZero()) continue;
    const double angle = std::atan2(n0.cross(n1).norm(), n0.dot(n1)) * 180.0 / M_PI;
    result.max_dihedral_deg = std::max(result.max_dihedral_deg, angle);
    if (!crease[e]) continue;
    ++result.crease_edges;
    result.crease_length += (mesh.positions[topo.edges[e][0]] - mesh.positions[topo.edges[e][1]]).norm();
  }
  return result;
}

}  // namespace stripweave
