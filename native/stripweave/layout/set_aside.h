// Components set aside: the layout of the parts a design leaves valid
// (issue 18: an assembly whose weave leaves a region red on one solid still
// gets the other solids' patches, fitted and written as STEP).
//
// The loops of different connected components of the surface never meet, so
// each component's regions, primal vertices, edges and patches depend on its
// own loops alone: leaving a component's loops out changes nothing on the
// others. A component that holds a red region has no layout (paper §4.2:
// only a design whose regions are all discs primalizes); the others do.
//
// red_components(surface, arrangement, regions) -> per surface triangle 1
//   on a connected component of the surface that holds a red region.
// lies_on(path, mask) -> whether an embedded loop (its segments computed:
//   path_segments.h) lies on a triangle the mask marks (a loop never leaves
//   its component, so its first segment decides).
//
// compute_regions (regions.h) takes the mask: the regions on marked
// components are set aside, and validity is that of the others.
#pragma once

#include "stripweave/layout/regions.h"
#include "stripweave/strips/parameterization.h"

#include <cstdint>
#include <vector>

namespace stripweave {

std::vector<std::uint8_t> red_components(const Surface& surface, const LoopArrangement& arrangement,
                                         const Regions& regions);

bool lies_on(const LoopPath& path, const std::vector<std::uint8_t>& mask);

}  // namespace stripweave
