#include "stripweave/layout/set_aside.h"

#include "stripweave/surface/mesh_topology.h"

namespace stripweave {

std::vector<std::uint8_t> red_components(const Surface& s, const LoopArrangement& A, const Regions& G) {
  const Index nt = s.mesh.num_triangles();
  std::vector<Index> component;
  const Index count = triangle_components(s.topology, nt, component);
  std::vector<std::uint8_t> red_component(count, 0);
  for (Index t = 0; t < A.mesh.num_triangles(); ++t)
    if (G.regions[G.triangle_region[t]].colour == RegionColour::Red) red_component[component[A.parent_triangle[t]]] = 1;
  std::vector<std::uint8_t> mask(nt, 0);
  for (Index t = 0; t < nt; ++t) mask[t] = red_component[component[t]];
  return mask;
}

bool lies_on(const LoopPath& path, const std::vector<std::uint8_t>& mask) {
  for (const PathSegment& seg : path.segments)
    if (seg.triangle != kInvalid) return mask[seg.triangle] != 0;
  return false;
}

}  // namespace stripweave
