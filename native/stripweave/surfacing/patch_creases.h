// Patch creases: does a quad patch of the layout lie over a crease of the
// part? A bicubic patch is C2 inside, so it cannot follow a crease that runs
// through it (rather than along one of its sides, where the seam is sharp
// and C0); refinement only narrows the rounded band, linearly in the span
// width, and rings beside it. Such a patch is a property of the layout (a
// strip that should have run along the feature curve, paper §5.6), and the
// refit reports it per patch instead of refining in vain.
//
// A crease is what the surface stage decided once (surface/creases.h: every
// sharp B-rep edge; on a mesh, the long feature curves, not scan noise), the
// same set the layout conforms to. A patch mesh's dihedral angles alone would
// be a third definition: on a scan they flag the noise ridges the surface
// stage dropped as creases, and patches that are smooth on the part would be
// reported as laid over creases.
//
// crease_locator(surface) -> the surface's crease edges as segments in model
//   units (an empty locator when the part has no crease).
//
// patch_creases(mesh, creases, test)
//   Input   the patch mesh (its triangles counter-clockwise from outside,
//           model units), the crease locator, and the test: the crease
//           angle in degrees and the distance (model units) within which a
//           point lies on a crease.
//   Rule    an interior edge of the patch mesh lies over a crease when
//           - it lies on one (both ends and its middle within the distance):
//             a patch cut from the solver mesh, whose edges along a crease
//             are pieces of the crease's own edges; or
//           - the patch mesh folds there by more than the crease angle and
//             its middle is within one edge length of a crease: a network
//             meshed independently of the solver mesh (by hand, or a
//             coarser sampling of the part) folds on its own edges beside
//             the crease, not on it.
//   Output  PatchCreases: the count and length of those edges, and the
//           largest dihedral angle between the normals of the two triangles
//           at one of them (0 when there is none).
#pragma once

#include "stripweave/cgal/segment_locator.h"
#include "stripweave/surface/surface.h"

namespace stripweave {

struct PatchCreases {
  double max_dihedral_deg = 0;
  Index crease_edges = 0;
  double crease_length = 0;  // model units
};

struct CreaseTest {
  double angle_deg = 30;
  double on_distance = 0;  // model units
};

SegmentLocator crease_locator(const Surface& surface);

PatchCreases patch_creases(const TriangleMesh& mesh, const SegmentLocator& creases, const CreaseTest& test);

}  // namespace stripweave
