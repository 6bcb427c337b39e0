// symmetric_surface: the solver mesh made exactly mirror-symmetric (paper
// §5.8: design on one part M0, transferred to the other by psi), so that the
// elastica graph, the loops, the field and the layout can be symmetric: on a
// remeshed part the two halves are triangulated differently, and a loop's
// mirror image searched there strays by a fraction of an edge per step
// (measured: up to 3% of the diagonal on a mirrored box at 8K triangles).
//
// symmetric_surface(surface, reflection) -> a Surface whose mesh is M0 (the
//   part on the normal's side of the plane, triangles that cross the plane cut
//   there, vertices within a tenth of a mean edge of the plane snapped onto
//   it) and its mirror image, welded along the plane. Per-vertex data (normal,
//   principal curvatures and directions) comes from the vertex it was, or is
//   interpolated along the cut edge, and is mirrored on the other half; edge
//   classes and feature curves follow the original edges; a mirrored
//   triangle's source B-rep face is the face of the original triangle nearest
//   to it. The similarity, the source B-rep and mesh are shared.
//   InputError when the plane misses the surface (nothing on one side).
//   A rotation goes to rotation_symmetric_surface (rotation_surface.h).
#pragma once

#include "stripweave/surface/surface.h"
#include "stripweave/symmetry/symmetry.h"

namespace stripweave {

Surface symmetric_surface(const Surface& surface, const Symmetry& symmetry);

}  // namespace stripweave
