// design_assessment: what automatic weaving (issue 6; workbench weave.py)
// asks of a design before it adds a strip, in one call.
//
// assess_design(design, extra_loops, seeds_per_region) -> DesignAssessment
//   Input : a derived design (strips/design_state.h: its strips' embedded
//           loops, their coverage and the cross field), candidate loops of
//           its session to add (embedded here: loop_path), and how many seed
//           points a region gets (0: none, and no anchors and no coverage:
//           what scoring a candidate needs).
//   Output: the arrangement of the design's loops plus the candidates
//           (loop_arrangement.h) and its regions (regions.h) under the
//           design's singularities: a candidate moves them a little, which
//           is ignored (the weave re-assesses once it derives the strip);
//           and, when seeds_per_region > 0, per region its seed points,
//           crossing anchors and bridge anchors, and the largest area no
//           strip of the design covers (weave_seeds.h; the candidates'
//           coverage is not known before they are derived). All positions
//           are in normalized units, as the surface's.
//   Cost : dominated by the arrangement and the regions (about 50 ms at 30K
//          triangles; time_ms says).
//
// nearest_surface_vertex(surface, point) -> the vertex nearest to a point
//   (normalized units); ties go to the lowest index. Linear: for the odd
//   query (the weave's principal anchors), not for loops.
#pragma once

#include "stripweave/layout/loop_arrangement.h"
#include "stripweave/layout/regions.h"
#include "stripweave/layout/weave_seeds.h"
#include "stripweave/strips/design_state.h"

#include <vector>

namespace stripweave {

struct DesignAssessment {
  LoopArrangement arrangement;
  Regions regions;
  std::vector<std::vector<SeedPoint>> seeds;                   // per region (empty lists: no seeds asked)
  std::vector<std::vector<CrossingAnchor>> crossing, bridges;  // per region, when seeds are asked
  UncoveredArea uncovered;                                     // the design's strips only
  double time_ms = 0;
};

DesignAssessment assess_design(const DesignState& design, const std::vector<Loop>& extra_loops,
                               int seeds_per_region);

Index nearest_surface_vertex(const Surface& surface, const Vec3& point);

}  // namespace stripweave
