// image_distance: how far a polyline's image under a symmetry is from another
// polyline (a loop's mirror image from the loop that should be it).
//
// image_distance(symmetry, k, a, b) -> the largest distance from a point of
//   psi^k(a) to the polyline b (point to segment), in the polylines' units:
//   one-sided Hausdorff. Infinite when either is empty. Used to skip an image
//   that coincides with its original (a loop that is its own mirror image)
//   and to check that a design is symmetric.
// Brute force, O(|a| |b|): loops have hundreds of points.
#pragma once

#include "stripweave/symmetry/symmetry.h"

#include <vector>

namespace stripweave {

double image_distance(const Symmetry& symmetry, int k, const std::vector<Vec3>& a, const std::vector<Vec3>& b);

}  // namespace stripweave
