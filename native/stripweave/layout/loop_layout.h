// loop_layout: the layout stage from embedded loops, the entry that the
// regions and layout bindings, the weave's predictions and the fit's patch
// network share.
//
// arrange_loops(surface, paths, singularities, set_aside = {}) -> ArrangedLoops
//   Input : loops embedded on the surface (their segments are computed here,
//           in place: path_segments.h), the cross field's singularities
//           (cross_field.h), and optionally, per surface triangle, the
//           components left out of the layout (set_aside.h).
//   Output: the loops' arrangement (loop_arrangement.h), its regions
//           (regions.h), and the milliseconds each step took.
//
// layout_loops(surface, paths, singularities, primal, pins, symmetries,
//              routes, set_aside_red = false) -> LoopLayout
//   arrange_loops, then, if primal, the quad layout (quad_layout.h) with
//   the design's vertex pins, symmetries and hand-routed edges.
//   set_aside_red: where a region stays red, the layout of the components
//   that hold none (set_aside.h): those components' loops alone, the red
//   components' regions set aside. A red region has no layout (paper §4.2),
//   but loops of different components never meet, so the others' layout is
//   the one they have alone. When every component holds a red region, the
//   full (invalid) layout.
#pragma once

#include "stripweave/strips/edge_route.h"
#include "stripweave/layout/quad_layout.h"
#include "stripweave/layout/regions.h"
#include "stripweave/symmetry/symmetry.h"

#include <cstdint>
#include <vector>

namespace stripweave {

struct ArrangedLoops {
  LoopArrangement arrangement;
  Regions regions;
  double embed_ms = 0, arrangement_ms = 0, regions_ms = 0;
};

struct LoopLayout {
  ArrangedLoops computed;
  QuadLayout layout;  // empty unless primal
  double layout_ms = 0;
};

ArrangedLoops arrange_loops(const Surface& surface, std::vector<LoopPath>& paths,
                            const std::vector<Singularity>& singularities,
                            const std::vector<std::uint8_t>& set_aside = {});

LoopLayout layout_loops(const Surface& surface, std::vector<LoopPath>& paths,
                        const std::vector<Singularity>& singularities, bool primal,
                        const std::vector<Vec3>& pins = {}, const std::vector<Symmetry>& symmetries = {},
                        const std::vector<EdgeRoute>& routes = {}, bool set_aside_red = false);

}  // namespace stripweave
