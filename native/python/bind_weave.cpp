// Bindings for automatic weaving (issue 6; workbench/stripweave/weave.py):
// the assessment of a design, optionally with candidate loops added, and
// where to seed the next strip. Geometry stays native; Python only decides.
//
// design_loops(design_state) -> [Loop]
//   The design's loops, in strip order (for regions() and candidates).
// weave_assessment(design_state, extra_loops=[], seeds_per_region=3) -> dict
//   assess_design (layout/design_assessment.h) as a dict.
//   The regions (paper §4.2) of the design's loops plus `extra_loops`, with
//   the design's cross-field singularities (a candidate loop moves them a
//   little; that is ignored), without the refined mesh. seeds_per_region=0
//   skips the seeds and the coverage (scoring a candidate). Keys (model units):
//     regions   [{"valence", "disc", "colour", "total_curvature",
//                 "ideal_valence", "area", "euler_characteristic", "genus",
//                 "boundaries" (its boundary cycles), "open_sides" (its sides
//                 along the open boundary, regions.h), "on_open_boundary" (some of
//                 its boundary is open boundary, regions.h), "singularities" (count),
//                 "singularity_quarters" (each one's index in quarters: +1 at a
//                 cube corner, -1 where five patches meet),
//                 "seeds": [[x,y,z], ...], "clearance": [...]}]
//               seeds by layout/weave_seeds.h (the first is the centre);
//               "crossing_anchors": [[x,y,z,dx,dy,dz], ...] across the arcs
//               that have the region on both sides (weave_seeds.h);
//               "bridge_anchors": [[x,y,z,dx,dy,dz], ...] along the
//               seeds_per_region shortest bridges between its boundary pieces
//               (weave_seeds.h);
//               "excess_extrema", "crease_problem", and for a crease region
//               "crease_seed" [x,y,z] (crease_structure.h: where a loop
//               across the crease would resolve it; where a rim of the
//               region lacks crossings and it has no other problem,
//               crease_rims.h, the rim's seed) and "crease_seed_across"
//               [dx,dy,dz] (the direction across the crease there; zero if
//               none); "crease_rim_lack" (bind_regions.cpp)
//     valid, crossings, arcs, colours {"red","orange","yellow","crease","none"}
//     uncovered {"found", "area", "largest_area", "surface_area", "point",
//                "clearance"}: what no strip covers (the design's strips only)
//     time_ms
// loop_anchor(session, loop, point) -> [x, y, z, dx, dy, dz]
//   The directional anchor (a g' node: its tail vertex and tangent) of the
//   loop nearest to `point`: re-searching the design from it is fast and
//   deterministic, where two positional anchors are slow.
// principal_anchors(surface, point) -> [[x,y,z,dx,dy,dz], [..]]
//   Directional anchors at the surface vertex nearest to `point` along its
//   minimum and maximum principal directions (§5.5: the directions good loops
//   follow). A one-direction query is much faster than the all-directions
//   hover query: the fallback when that one runs too long.
#include "bind.h"
#include "bind_regions.h"

#include "stripweave/core/error.h"
#include "stripweave/layout/design_assessment.h"
#include "stripweave/strips/design_state.h"

#include <pybind11/stl.h>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

namespace {

std::vector<double> model_point(const Surface& s, const Vec3& p) {
  const Vec3 q = s.similarity.to_model(p);
  return {q.x(), q.y(), q.z()};
}

// Region r's directional anchors [x, y, z, dx, dy, dz] (model units; the similarity only scales).
py::list anchors_of(const Surface& s, const std::vector<std::vector<CrossingAnchor>>& anchors, size_t r) {
  py::list out;
  if (r < anchors.size())
    for (const CrossingAnchor& c : anchors[r]) {
      std::vector<double> anchor = model_point(s, c.point);
      anchor.insert(anchor.end(), {c.direction.x(), c.direction.y(), c.direction.z()});
      out.append(anchor);
    }
  return out;
}

double model_length(const Surface& s, double x) { return std::isinf(x) ? -1.0 : x * s.similarity.scale; }

}  // namespace

void bind_weave(py::module_& m) {
  m.def("design_loops", [](const DesignState& d) {
        std::vector<Loop> out;
        for (const DesignStrip& s : d.strips()) out.push_back(s.loop);
        return out;
      },
      py::arg("design_state"), "The design's loops in strip order");

  m.def("weave_assessment", [](DesignState& d, const std::vector<Loop>& extra, int seeds_per_region) {
        const Surface& s = d.surface();
        const double scale = s.similarity.scale, scale2 = scale * scale;
        DesignAssessment assessment;
        {
          stripweave_python::NativeCall release;
          assessment = assess_design(d, extra, seeds_per_region);
        }
        const LoopArrangement& arrangement = assessment.arrangement;
        const Regions& regions = assessment.regions;
        const auto& seeds = assessment.seeds;
        const auto& crossing = assessment.crossing;
        const auto& bridges = assessment.bridges;
        const UncoveredArea& uncovered = assessment.uncovered;
        py::list list;
        py::dict colours;
        for (const char* c : {"red", "orange", "yellow", "crease", "none"}) colours[c] = 0;
        for (size_t r = 0; r < regions.regions.size(); ++r) {
          const Region& g = regions.regions[r];
          py::dict x;
          put_region_keys(x, g, scale2);
          x["singularities"] = g.singularities.size();
          std::vector<int> quarters;
          for (Index k : g.singularities) quarters.push_back(d.field().singularities[k].quarter_index);
          x["singularity_quarters"] = quarters;
          // Where a loop across the crease would resolve a crease region (crease_structure.h).
          const Index split = regions.creases.regions[r].split_vertex;
          if (g.crease_problem != CreaseProblem::None && split != kInvalid) {
            x["crease_seed"] = model_point(s, arrangement.mesh.positions[split]);
            const Vec3& across = regions.creases.regions[r].split_across;   // the similarity only scales
            x["crease_seed_across"] = std::vector<double>{across.x(), across.y(), across.z()};
          }
          py::list pts, clear;
          for (const SeedPoint& p : seeds[r]) {
            pts.append(model_point(s, p.point));
            clear.append(model_length(s, p.clearance));
          }
          x["seeds"] = pts;
          x["crossing_anchors"] = anchors_of(s, crossing, r);
          x["bridge_anchors"] = anchors_of(s, bridges, r);
          x["clearance"] = clear;
          list.append(x);
          const char* c = colour_name(g.colour);
          colours[c] = colours[c].cast<int>() + 1;
        }
        py::dict u;
        u["found"] = uncovered.found;
        u["area"] = uncovered.total_area * scale2;
        u["largest_area"] = uncovered.area * scale2;
        u["surface_area"] = uncovered.surface_area * scale2;
        u["point"] = uncovered.found ? py::cast(model_point(s, uncovered.seed.point)) : py::none();
        u["clearance"] = model_length(s, uncovered.seed.clearance);
        py::dict out;
        out["regions"] = list;
        out["valid"] = regions.valid;
        out["crossings"] = arrangement.crossings;
        out["arcs"] = arrangement.arcs.size();
        out["colours"] = colours;
        out["uncovered"] = u;
        out["time_ms"] = assessment.time_ms;
        return out;
      },
      py::arg("design_state"), py::arg("extra_loops") = std::vector<Loop>(), py::arg("seeds_per_region") = 3,
      "Regions, colours and seed points of the design (plus candidate loops), and its largest uncovered area");

  m.def("loop_anchor", [](const LoopSession& session, const Loop& loop, const std::vector<double>& point) {
        const Surface& s = session.surface();
        if (point.size() != 3) throw InputError("loop_anchor needs a point (x, y, z)");
        if (loop.nodes.empty()) throw InputError("loop_anchor: the loop has no nodes");
        const Vec3 p = s.similarity.to_normalized(Vec3(point[0], point[1], point[2]));
        const ElasticaGraph& g = session.graph();
        for (Index n : loop.nodes) (void)g.tail.at(n);  // a loop of another session: an error, not a crash
        const Index best = loop_anchor_node(s, g, loop, p);
        const Vec3 q = s.similarity.to_model(s.mesh.positions[g.tail.at(best)]);
        const Vec3 t = g.tangent(s, best);
        return std::vector<double>{q.x(), q.y(), q.z(), t.x(), t.y(), t.z()};
      },
      py::arg("session"), py::arg("loop"), py::arg("point"),
      "The loop's directional anchor nearest to a point (model units)");

  m.def("principal_anchors", [](const Surface& s, const std::vector<double>& point) {
        if (point.size() < 3) throw InputError("principal_anchors needs a point (x, y, z)");
        const Vec3 p = s.similarity.to_normalized(Vec3(point[0], point[1], point[2]));
        const Index best = nearest_surface_vertex(s, p);
        if (best == kInvalid) throw InputError("principal_anchors: the surface has no vertices");
        const Vec3 q = s.similarity.to_model(s.mesh.positions[best]);
        std::vector<std::vector<double>> out;
        for (const auto* dirs : {&s.d_min, &s.d_max}) {
          if (static_cast<Index>(dirs->size()) <= best) continue;
          const Vec3 d = (*dirs)[best];
          if (!(d.norm() > 0)) continue;
          out.push_back({q.x(), q.y(), q.z(), d.x(), d.y(), d.z()});
        }
        return out;
      },
      py::arg("surface"), py::arg("point"),
      "Directional anchors along the principal directions at the vertex nearest to a point (model units)");
}

}  // namespace stripweave_python
