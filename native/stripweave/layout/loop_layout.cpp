#include "stripweave/layout/loop_layout.h"

#include "stripweave/layout/set_aside.h"
#include "stripweave/strips/path_segments.h"

#include <algorithm>
#include <chrono>

namespace stripweave {

namespace {

using Clock = std::chrono::steady_clock;
double millis(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

LoopLayout layout_of(const Surface& s, std::vector<LoopPath>& paths, const std::vector<Singularity>& singular,
                     bool primal, const std::vector<Vec3>& pins, const std::vector<Symmetry>& symmetries,
                     const std::vector<EdgeRoute>& routes, const std::vector<std::uint8_t>& set_aside) {
  LoopLayout out;
  out.computed = arrange_loops(s, paths, singular, set_aside);
  if (primal) {
    const auto t0 = Clock::now();
    out.layout = build_quad_layout(s, out.computed.arrangement, out.computed.regions, singular, pins, symmetries,
                                   routes);
    out.layout_ms = millis(t0, Clock::now());
  }
  return out;
}

}  // namespace

ArrangedLoops arrange_loops(const Surface& s, std::vector<LoopPath>& paths, const std::vector<Singularity>& singular,
                            const std::vector<std::uint8_t>& set_aside) {
  ArrangedLoops c;
  const auto t0 = Clock::now();
  for (LoopPath& lp : paths) lp.segments = path_segments(s, lp.path, lp.closed);
  const auto t1 = Clock::now();
  c.arrangement = build_loop_arrangement(s, paths);
  const auto t2 = Clock::now();
  c.regions = compute_regions(s, c.arrangement, singular, set_aside);
  const auto t3 = Clock::now();
  c.embed_ms = millis(t0, t1);
  c.arrangement_ms = millis(t1, t2);
  c.regions_ms = millis(t2, t3);
  return c;
}

LoopLayout layout_loops(const Surface& s, std::vector<LoopPath>& paths, const std::vector<Singularity>& singular,
                        bool primal, const std::vector<Vec3>& pins, const std::vector<Symmetry>& symmetries,
                        const std::vector<EdgeRoute>& routes, bool set_aside_red) {
  LoopLayout full = layout_of(s, paths, singular, primal, pins, symmetries, routes, {});
  if (!set_aside_red || full.computed.regions.valid) return full;
  const std::vector<std::uint8_t> red = red_components(s, full.computed.arrangement, full.computed.regions);
  if (std::all_of(red.begin(), red.end(), [](std::uint8_t x) { return x != 0; })) return full;
  std::vector<LoopPath> kept;
  for (LoopPath& p : paths)
    if (!lies_on(p, red)) kept.push_back(std::move(p));
  return layout_of(s, kept, singular, primal, pins, symmetries, routes, red);
}

}  // namespace stripweave
