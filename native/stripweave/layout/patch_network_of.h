// patch_network_of(surface, arrangement, layout) -> PatchNetwork
//   The hand-over from primalization to surfacing (surfacing/patch_network.h):
//   the layout's vertices, edges and quad patches in model units, each patch
//   as its own disc mesh (the refined triangles of the patch, with vertices
//   split where the primal edges cut, so a vertex several corners share is
//   one patch-mesh vertex per corner) and the B-rep face of each triangle.
//   Patches that are not clean quads (QuadLayout::problems), that fold back
//   around a slit (PrimalPatch::folds_back), or one of whose sides is an edge
//   of a single point, are left out, and so are the edges no
//   handed-over patch has as a side (re-indexed: the network's edges are those
//   of its patches, in the layout's order; its vertices are the layout's).
#pragma once

#include "stripweave/layout/quad_layout.h"
#include "stripweave/surfacing/patch_network.h"

namespace stripweave {

PatchNetwork patch_network_of(const Surface& surface, const LoopArrangement& arrangement, const QuadLayout& layout);

}  // namespace stripweave
