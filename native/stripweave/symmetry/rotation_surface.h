// rotation_symmetric_surface: the solver mesh made exactly symmetric under a
// rotation of order n (paper §5.8: design on one part M0, transferred to the
// others by psi^k), as symmetric_surface does for a reflection. A loop's
// image searched afresh on a remeshed hub strays from the image of the loop
// by more than two solver edges, and the weave refuses every symmetric
// strip; on a mesh that is its own image the graph, the loops and the field
// are.
//
// rotation_symmetric_surface(surface, rotation) -> a Surface whose mesh is
//   n copies of one sector M0 (the part between the half-planes at angles 0
//   and 2 pi / n about the axis; triangles across them cut there, vertices
//   within a tenth of a mean edge of a half-plane or of the axis snapped onto
//   it), each the image of M0 under psi^k, welded along the half-planes. So
//   that copy k's far side meets copy k+1's near side vertex for vertex, each
//   side of M0 gets the other side's seam vertices mapped onto it (a seam
//   edge split where one lands, a vertex within the snap distance taken as
//   that one). Per-vertex data (normal, principal curvatures, directions)
//   comes from the original surface at the vertex's nearest point and is
//   rotated with the copy; an edge is a feature when its middle lies on an
//   original feature edge; a triangle's source B-rep face is that of the
//   original triangle nearest it. The similarity, B-rep and source mesh are
//   shared.
//   InputError when the result is not the surface it should be (its genus,
//   boundary loops or components differ from the original's: the part is not
//   rotation-symmetric enough for one sector to stand for the others) or a
//   sector is empty.
#pragma once

#include "stripweave/surface/surface.h"
#include "stripweave/symmetry/symmetry.h"

#include <optional>

namespace stripweave {

// sector_start, when given (a direction across the axis): the sector starts
// there instead of where the cut is quietest. A dihedral group's sector runs
// between two of its mirror planes' neighbours, from -pi/n to pi/n about one
// mirror, so that on a mesh already exact under that mirror the sector is its
// own mirror image and the n copies are exact under every mirror of the group
// (the seam at -pi/n mirrored is the seam at pi/n, as the rotation maps it).
Surface rotation_symmetric_surface(const Surface& surface, const Symmetry& rotation,
                                   const std::optional<Vec3>& sector_start = std::nullopt);

}  // namespace stripweave
