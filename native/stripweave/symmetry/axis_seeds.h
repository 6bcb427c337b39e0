// axis_seeds: where loops pass a rotation's axis (paper §5.8).
//
// Where the axis of a rotation of order n meets the surface (a fixed point of
// the rotation), no loop may pass: its n - 1 images pass there too, and n
// loops crossing in one point are no arrangement. A symmetric quad layout
// puts a primal vertex there instead, of valence n, in a region bounded by n
// images of one loop that passes BESIDE the point: over a smooth cap around
// the point the loop runs as a chord at some clearance c, and its images are
// the sides of an n-gon of apothem c. A loop through one anchor beside one
// fixed point closes wherever is cheapest and passes the other fixed point
// (a hub's bottom, when the anchor is on its top) at any distance, through
// it as likely as not; so a seed holds one anchor beside every fixed point.
//
// axis_points(surface, rotation) -> the fixed points: the axis line's
//   crossings of the surface, in order along the axis, each with the
//   surface's unit normal there (the mean of the crossed triangles') and its
//   cap radius: the geodesic distance (along mesh edges) from the point to
//   the nearest vertex on a crease or the open boundary, or whose normal has
//   turned more than 45 degrees from the normal at the point. Over that cap
//   a loop beside the point is a chord of a near-flat disc. Points where the
//   surface runs along the axis (normal within 60 degrees of normal to it) are
//   left out: no chord passes them.
// axis_seed(surface, rotation, points, fraction, locator) -> one directional
//   anchor per fixed point, all for one loop: at the clearance
//   fraction * cos(pi / n) * cap radius from the point (at fraction 1 the
//   n-gon's corners, where images cross, lie on the cap's rim), on the side of
//   a fixed radial direction r (normal to the axis, the same for every point),
//   re-projected onto the surface, running along normal x r (across r: a
//   chord; the sense flips between caps that face opposite ways, as a loop
//   over a hub's top runs back under its bottom).
//   Normalized units, as the surface's.
//   Cost: linear in the surface (one pass over the triangles, one Dijkstra
//   per fixed point stopped at the cap's rim).
#pragma once

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/elastica/loop_search.h"
#include "stripweave/surface/surface.h"
#include "stripweave/symmetry/symmetry.h"

#include <vector>

namespace stripweave {

struct AxisPoint {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::Zero();  // unit, outward
  double cap_radius = 0;       // normalized units
};

std::vector<AxisPoint> axis_points(const Surface& surface, const Symmetry& rotation);

std::vector<Anchor> axis_seed(const Surface& surface, const Symmetry& rotation, const std::vector<AxisPoint>& points,
                              double fraction, const SurfaceLocator& locator);

}  // namespace stripweave
