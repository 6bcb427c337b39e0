// Patch creases: does a quad patch of the layout lie over a crease of the
// source? A bicubic patch is C2 inside, so it cannot follow a crease that
// runs through it (rather than along one of its sides, where the seam is
// sharp and C0); refinement only narrows the rounded band, linearly in the
// span width, and rings beside it. Such a patch is a property of the layout
// (a strip that should have run along the feature curve, paper §5.6), and
// the refit reports it per patch instead of refining in vain.
//
// Input   the patch mesh (its triangles counter-clockwise from outside,
//         model units), the crease angle in degrees (the surface stage's
//         feature angle, 30 by default).
// Output  PatchCreases: the largest dihedral angle between the normals of
//         two triangles sharing an interior edge of the patch mesh
//         (180: the patch folds over a thin wall, both sides in one patch),
//         and the count and length of the interior edges above the crease
//         angle (dihedral_feature_edges of the surface stage).
#pragma once

#include "stripweave/surface/triangle_mesh.h"

namespace stripweave {

struct PatchCreases {
  double max_dihedral_deg = 0;
  Index crease_edges = 0;
  double crease_length = 0;  // model units
};

PatchCreases patch_creases(const TriangleMesh& mesh, double crease_angle_deg);

}  // namespace stripweave
