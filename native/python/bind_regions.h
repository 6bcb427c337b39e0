// Shared by the regions and layout bindings: the arrangement and regions of
// a set of embedded loops, and their dict form (bind_regions.cpp).
#pragma once

#include "bind.h"

#include "stripweave/layout/loop_layout.h"
#include "stripweave/layout/regions.h"
#include "stripweave/strips/design_state.h"

#include <chrono>

namespace stripweave_python {

using Clock = std::chrono::steady_clock;
inline double millis(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// The arrangement and regions of embedded loops (layout/loop_layout.h).
using Computed = stripweave::ArrangedLoops;

// The session's loops embedded on its surface (call without the GIL).
std::vector<stripweave::LoopPath> embed_loops(const stripweave::LoopSession& session,
                                              const std::vector<stripweave::Loop>& loops);

// Loops given as embedded paths: dicts with per point 'vertex' (or -1), 'edge' (or -1)
// and 't' along surface.edges[edge], and 'closed' (InputError on a bad one).
std::vector<stripweave::LoopPath> paths_from_dicts(const stripweave::Surface& s,
                                                   const std::vector<pybind11::dict>& paths);

// A region's assessment keys that regions() and weave_assessment() share (valence, disc,
// colour, total_curvature, ideal_valence, euler_characteristic, boundaries, open_sides,
// on_open_boundary, genus, area in model units squared: `scale2`, excess_extrema,
// crease_problem, crease_excess, set_aside: on a component the layout left out,
// layout/set_aside.h), into `d`.
void put_region_keys(pybind11::dict& d, const stripweave::Region& r, double scale2);

// The keys documented in bind_regions.cpp.
pybind11::dict regions_dict(const stripweave::Surface& s, const std::vector<stripweave::Singularity>& singular,
                            const Computed& c, bool details);

// Primalization (§7) as methods of DesignState (bind_layout.cpp).
std::vector<stripweave::Singularity> singularities_from(const stripweave::Surface& s,
                                                       const std::vector<stripweave::Index>& vertices,
                                                       const std::vector<int>& quarter_indices);

void bind_layout(pybind11::module_& m, pybind11::class_<stripweave::DesignState, std::shared_ptr<stripweave::DesignState>>& state);

}  // namespace stripweave_python
