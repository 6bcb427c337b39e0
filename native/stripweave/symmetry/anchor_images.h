// anchor_images: a strip's anchor on every other part of a symmetric surface
// (paper §5.8: a design made on one part M0 is transferred to the others).
//
// anchor_images(symmetry, anchor, locator) -> per group element psi^k,
//   k = 1 .. symmetry.images(), the anchor mapped by psi^k and re-projected:
//   its point onto the nearest surface point, its direction (if any) mapped
//   and projected into that triangle's plane. The loop search through the
//   image anchor finds the image loop where the solver mesh is symmetric, and
//   the nearest loop where it is only close to symmetric.
//   InputError if a mapped direction is normal to the surface there.
#pragma once

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/elastica/loop_search.h"
#include "stripweave/symmetry/symmetry.h"

#include <vector>

namespace stripweave {

std::vector<Anchor> anchor_images(const Symmetry& symmetry, const Anchor& anchor, const TriangleMesh& mesh,
                                  const SurfaceLocator& locator);

}  // namespace stripweave
