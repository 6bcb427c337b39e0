#include "stripweave/surfacing/patch_creases.h"

#include "stripweave/surface/mesh_topology.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

SegmentLocator crease_locator(const Surface& s) {
  std::vector<Segment3> segments;
  for (Index e = 0; e < s.topology.num_edges(); ++e)
    if (s.edge_class[e] == EdgeClass::Feature) {
      const auto& [a, b] = s.topology.edges[e];
      segments.push_back({s.similarity.to_model(s.mesh.positions[a]), s.similarity.to_model(s.mesh.positions[b])});
    }
  return SegmentLocator(segments);
}

namespace {
double dihedral_deg(const TriangleMesh& mesh, Index t0, Index t1) {
  const Vec3 n0 = triangle_normal_area2(mesh, t0), n1 = triangle_normal_area2(mesh, t1);
  if (n0.isZero() || n1.isZero()) return 0;
  return std::atan2(n0.cross(n1).norm(), n0.dot(n1)) * 180.0 / M_PI;
}
}  // namespace

PatchCreases patch_creases(const TriangleMesh& mesh, const SegmentLocator& creases, const CreaseTest& test) {
  PatchCreases result;
  if (mesh.num_triangles() == 0 || creases.empty()) return result;
  const MeshTopology topo = MeshTopology::build(mesh);
  for (Index e = 0; e < topo.num_edges(); ++e) {
    const auto& et = topo.edge_triangles[e];
    if (et[1] == kInvalid) continue;
    const Vec3& a = mesh.positions[topo.edges[e][0]];
    const Vec3& b = mesh.positions[topo.edges[e][1]];
    const double length = (b - a).norm(), middle = creases.distance(0.5 * (a + b));
    const double angle = dihedral_deg(mesh, et[0], et[1]);
    const bool on = middle <= test.on_distance && creases.distance(a) <= test.on_distance &&
                    creases.distance(b) <= test.on_distance;
    const bool folds_by = angle > test.angle_deg && middle <= length;
    if (!on && !folds_by) continue;
    result.max_dihedral_deg = std::max(result.max_dihedral_deg, angle);
    ++result.crease_edges;
    result.crease_length += length;
  }
  return result;
}

}  // namespace stripweave
