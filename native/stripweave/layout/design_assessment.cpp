#include "stripweave/layout/design_assessment.h"

#include "stripweave/core/error.h"

#include <chrono>
#include <limits>

namespace stripweave {

DesignAssessment assess_design(const DesignState& design, const std::vector<Loop>& extra_loops,
                               int seeds_per_region) {
  if (seeds_per_region < 0) throw InputError("seeds_per_region must be 0 (no seeds) or more");
  const auto t0 = std::chrono::steady_clock::now();
  const Surface& s = design.surface();
  std::vector<LoopPath> paths;
  std::vector<const std::vector<std::uint8_t>*> covered;
  for (const DesignStrip& strip : design.strips()) {
    paths.push_back(strip.path);
    covered.push_back(&strip.strip.covered);
  }
  for (const Loop& loop : extra_loops) paths.push_back(loop_path(design.session(), loop));
  DesignAssessment out;
  out.arrangement = build_loop_arrangement(s, paths);
  out.regions = compute_regions(s, out.arrangement, design.field().singularities);
  out.seeds.resize(out.regions.regions.size());
  if (seeds_per_region > 0) {
    out.seeds = region_seed_points(out.arrangement, out.regions, seeds_per_region);
    out.crossing = crossing_anchors(out.arrangement, out.regions);
    out.bridges = bridge_anchors(out.arrangement, out.regions, seeds_per_region);
    out.uncovered = largest_uncovered_area(s, covered);
  }
  out.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

Index nearest_surface_vertex(const Surface& surface, const Vec3& point) {
  Index best = kInvalid;
  double best_d = std::numeric_limits<double>::infinity();
  for (Index v = 0; v < surface.mesh.num_vertices(); ++v) {
    const double d = (surface.mesh.positions[v] - point).squaredNorm();
    if (d < best_d) best_d = d, best = v;
  }
  return best;
}

}  // namespace stripweave
