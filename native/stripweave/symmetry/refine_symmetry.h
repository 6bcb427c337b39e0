// refine_symmetry: fit a candidate symmetry to the surface (a few steps of
// iterative closest points), so that a plane or axis found from moments or
// feature points lands where the surface's symmetry really is.
//
// refine_symmetry(candidate, samples, locator, iterations) -> the refined
//   symmetry (same kind and order). Each step pairs every sample p with the
//   surface point q closest to psi(p), then
//   - reflection: the normal is the principal direction of the differences
//     p - q (a reflection moves points along its normal), the plane passes
//     through the mean of the midpoints (p + q) / 2 along it;
//   - rotation: the best rigid motion p -> q (Kabsch) gives the axis (its
//     rotation's fixed direction) and a point on it (least squares of
//     (I - R) x = t); the order stays (the angle is 2 pi / order by
//     definition, only the axis is fitted).
//   Stops when the map moves less than 1e-10, when a step lowers the RMS
//   error by less than 1% (the best map so far is returned), or after
//   `iterations` steps.
// Why: the area centroid of a mesh whose two halves are triangulated
// differently is off by the meshing error of curved parts; ICP removes that
// bias, so a mirrored part's plane is found to ~1e-6 of the diagonal.
#pragma once

#include "stripweave/symmetry/symmetry_error.h"

namespace stripweave {

Symmetry refine_symmetry(const Symmetry& candidate, const std::vector<Vec3>& samples, const SurfaceLocator& locator,
                         int iterations = 8);

}  // namespace stripweave
