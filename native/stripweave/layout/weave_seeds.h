// Seed points for automatic weaving (issue 6): where the next strip should
// be proposed. The paper's tool leaves this to the user's eye (§4.2: the
// colours guide the user to regions that need strips); automatic weaving
// asks the same questions of the geometry.
//
// region_seed_points(arrangement, regions, count) -> per region, up to
//   `count` points (normalized units) by farthest-point sampling inside the
//   region: the first is the refined vertex farthest from the region's
//   border (its loops and open boundary), i.e. its centre in the sense of
//   the largest inscribed geodesic disc; each next one is farthest from the
//   border and the earlier ones. Distances are shortest paths along refined
//   mesh edges that do not cross the border. A region without border (no
//   loops yet, a closed surface) starts from the vertex farthest from its
//   lowest-numbered vertex. Deterministic: ties go to the lowest vertex id.
//   The clearance (distance to the border, +inf without one) of each point
//   comes with it.
//
// crossing_anchors(arrangement, regions) -> per region, directional anchors
//   (point, direction; normalized units) at the middle of each arc that has
//   the region on both sides, pointing across the arc. Such an arc's loop
//   does not separate the region (a lone meridian on a handle), and the loop
//   that crosses it there and comes back around is the cut that makes the
//   region a disc: the dual of the handle's other generator.
//
// bridge_anchors(arrangement, regions, count) -> per region, directional
//   anchors at the middle of the shortest bridge between two of its boundary
//   pieces (the connected sets of its border: loop and open-boundary edges),
//   pointing along the bridge; one per pair of pieces a shortest bridge joins,
//   the `count` shortest (the cheapest cuts: a range scan's region with thirty
//   holes has some ninety such pairs, and each anchor costs the weave a loop
//   query; the others come up once these cuts have changed the region); none
//   for a region with one piece or a region that is not red (assessment.h),
//   except a disc with two or more stretches of open boundary (regions.h),
//   whose pieces are those stretches and whose anchor points ACROSS the bridge:
//   the curve there crosses the region from side to side and parts the two
//   stretches (one along the bridge would leave both on each side of it). A region with b >= 2 boundary
//   cycles (an annulus between two loops around a boss, a plate's face around
//   a bore) becomes a disc only by cuts that join its boundaries, b - 1 of
//   them: no loop that stays inside it, however good, does. The shortest
//   bridge meets both boundaries orthogonally, the direction a loop crossing
//   them transversally (§6.2) takes, so the loop through its middle along it
//   is the cut's natural proposal; the region's centre proposes the loop of
//   its own best direction, which around a boss runs parallel to the
//   boundaries and splits the annulus into two.
//
// largest_uncovered_area(surface, covered) -> the largest edge-connected
//   set of surface triangles that no strip covers (`covered`: per strip, per
//   triangle 0/1), its area, the uncovered area in all, and its point
//   farthest from every covered triangle (the place a new strip adds most
//   coverage). Nothing uncovered: area 0 and no point.
#pragma once

#include "stripweave/layout/regions.h"

#include <cstdint>
#include <limits>

namespace stripweave {

struct SeedPoint {
  Vec3 point = Vec3::Zero();
  double clearance = std::numeric_limits<double>::infinity();
};

std::vector<std::vector<SeedPoint>> region_seed_points(const LoopArrangement& arrangement, const Regions& regions,
                                                       int count);

struct CrossingAnchor {
  Vec3 point = Vec3::Zero();
  Vec3 direction = Vec3::Zero();
};

std::vector<std::vector<CrossingAnchor>> crossing_anchors(const LoopArrangement& arrangement, const Regions& regions);

std::vector<std::vector<CrossingAnchor>> bridge_anchors(const LoopArrangement& arrangement, const Regions& regions,
                                                       int count);

struct UncoveredArea {
  double area = 0;        // of the largest uncovered component (normalized units squared)
  double total_area = 0;  // of all uncovered triangles
  double surface_area = 0;
  bool found = false;
  SeedPoint seed;
};

UncoveredArea largest_uncovered_area(const Surface& surface,
                                     const std::vector<const std::vector<std::uint8_t>*>& covered);

}  // namespace stripweave
