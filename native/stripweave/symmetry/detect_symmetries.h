// detect_symmetries: the global reflections and rotations of a surface
// (paper §5.8: "determined using (semi-)automatic methods [Mitra et al.
// 2013]").
//
// detect_symmetries(surface, options) -> [Symmetry], reflections first, each
//   with rms_error and max_error measured on every vertex (symmetry_error.h),
//   in the surface's (normalized) units, and each accepted only when
//   max_error <= options.tolerance (default 1e-3 of the diagonal, the fit's).
//   Rotations keep only their maximal order about an axis (order 6 implies 2
//   and 3: 6 is reported).
//
// Candidates, all through the area centroid (every symmetry fixes it):
//   - the three principal axes of the area moments (area_moments.h), each as a
//     reflection normal and as a rotation axis of orders 2..options.max_order;
//   - where two or three moments are (nearly) equal, so that the principal
//     axes are not determined (a cube, a hub with n >= 3 blades, whose mirror
//     planes are any of the plane of equal moments): directions from salient
//     points, the feature-curve junctions and ends and the points farthest
//     from the centroid (curvature extrema of the silhouette): centroid -> p
//     and p - q for pairs (a pair swapped by a reflection has p - q along the
//     normal; a rotation axis of a cube passes through a corner, a face
//     centre or an edge midpoint, which these directions reach).
// Each candidate is screened on a subsample with an early exit, refined
// (refine_symmetry.h) and verified on every vertex. Duplicates (same plane or
// axis within 1e-3) are merged, keeping the smaller error.
#pragma once

#include "stripweave/surface/surface.h"
#include "stripweave/symmetry/symmetry.h"

#include <vector>

namespace stripweave {

struct SymmetryOptions {
  double tolerance = 1e-3;  // max error accepted, in diagonals
  int max_order = 12;       // rotation orders tried: 2..max_order
  int salient_points = 16;  // at most this many salient points when moments are degenerate
};

std::vector<Symmetry> detect_symmetries(const Surface& surface, const SymmetryOptions& options = SymmetryOptions());

}  // namespace stripweave
