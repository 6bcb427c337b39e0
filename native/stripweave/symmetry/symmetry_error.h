// symmetry_error: how far a symmetry maps a surface off itself.
//
// symmetry_error(symmetry, samples, locator, give_up = inf)
//   -> {rms, max, pairs}: the distance from psi(p) to the surface (the
//   locator's mesh) over the samples p (points on that surface), RMS and max,
//   in the surface's units. Only the generator psi is measured: psi^k moves a
//   point at most k times as far, and a surface psi maps into itself is mapped
//   by every power. One-sided by design: psi is an isometry, so psi(M) inside
//   M means psi(M) = M up to a set of no area.
//   give_up: stop at the first sample farther than this (a candidate that is
//   clearly no symmetry costs a few queries, not one per sample); the result
//   then has complete = false and max = that distance.
//   pairs (with keep_pairs): per sample, the closest surface point to its
//   image (refine_symmetry fits the map to them).
#pragma once

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/symmetry/symmetry.h"

#include <limits>
#include <vector>

namespace stripweave {

struct SymmetryError {
  double rms = 0;
  double max = 0;
  bool complete = true;
  std::vector<Vec3> closest;  // per sample, with keep_pairs
};

SymmetryError symmetry_error(const Symmetry& symmetry, const std::vector<Vec3>& samples, const SurfaceLocator& locator,
                             double give_up = std::numeric_limits<double>::infinity(), bool keep_pairs = false);

}  // namespace stripweave
