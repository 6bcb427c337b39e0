// patch_network_of(surface, arrangement, layout) -> PatchNetwork
//   The hand-over from primalization to surfacing (surfacing/patch_network.h):
//   the layout's vertices, edges and quad patches in model units, each patch
//   as its own disc mesh (the refined triangles of the patch, with vertices
//   split where the primal edges cut, so a vertex several corners share is
//   one patch-mesh vertex per corner) and the B-rep face of each triangle.
//   Patches that are not clean quads (QuadLayout::problems) are left out.
#pragma once

#include "stripweave/layout/quad_layout.h"
#include "stripweave/surfacing/patch_network.h"

namespace stripweave {

PatchNetwork patch_network_of(const Surface& surface, const LoopArrangement& arrangement, const QuadLayout& layout);

}  // namespace stripweave
