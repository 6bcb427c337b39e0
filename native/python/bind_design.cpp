// Bindings of the design and strips stages (paper §4.1, §6): DesignState.
//
// Anchors, points, widths and strip coordinates cross in MODEL units.
// Recomputing a design releases the GIL.
#include "bind_regions.h"

#include "stripweave/core/error.h"
#include "stripweave/strips/design_state.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

namespace {

std::vector<StripSpec> specs_from(const Surface& s, const std::vector<std::vector<std::vector<double>>>& strips) {
  std::vector<StripSpec> specs;
  for (const auto& anchors : strips) {
    StripSpec spec;
    for (const auto& a : anchors) spec.anchors.push_back(anchor_from(s, a));
    try {
      check_anchor_chain(spec.anchors);
    } catch (const InputError& e) {
      throw InputError("strip " + std::to_string(specs.size() + 1) + ": " + e.what());
    }
    specs.push_back(std::move(spec));
  }
  return specs;
}

py::dict strip_dict(const Surface& s, const DesignStrip& d) {
  py::dict out = path_dict(s, d.path.path);
  out["closed"] = d.loop.closed;
  out["cost"] = d.loop.cost;
  out["width_left"] = d.strip.width_left;
  out["width_right"] = d.strip.width_right;
  out["stop_left"] = d.strip.stop_left;
  out["stop_right"] = d.strip.stop_right;
  out["area_fraction"] = d.strip.area_fraction;
  out["triangles"] = d.strip.triangles;
  // The loop is the isocurve across = 0 of its strip: |across| at the ends of
  // every loop segment, in the strip coordinates carried through S's
  // transitions (a check of exact alignment, model units).
  double across = 0;
  std::vector<Index> slot(d.strip.covered.size(), kInvalid);  // triangle -> its entry in coords
  for (size_t k = 0; k < d.strip.triangles.size(); ++k) slot[d.strip.triangles[k]] = static_cast<Index>(k);
  for (const PathSegment& seg : d.path.segments) {
    if (!d.strip.covered[seg.triangle]) continue;
    for (Index point : {seg.from, seg.to}) {
      const Vec3 b = barycentric_in(s, d.path.path, point, seg.triangle);
      const auto& c = d.strip.coords[slot[seg.triangle]];
      across = std::max(across, std::abs(b[0] * c[0].y() + b[1] * c[1].y() + b[2] * c[2].y()));
    }
  }
  out["loop_across_max"] = across;
  out["loop_nodes"] = d.loop.nodes;
  return out;
}

}  // namespace

void bind_design(py::module_& m) {
  auto state = py::class_<DesignState, std::shared_ptr<DesignState>>(
      m, "DesignState", "All derived state of a design: loops, cross field, parameterization, strips, mask")
      .def(py::init([](std::shared_ptr<LoopSession> session, bool features, bool boundary) {
             FieldOptions options;
             options.features = features;
             options.boundary = boundary;
             return std::make_shared<DesignState>(std::move(session), options);
           }),
           py::arg("session"), py::arg("features") = true, py::arg("boundary") = true)
      .def(
          "set_strips",
          [](DesignState& d, const std::vector<std::vector<std::vector<double>>>& strips) {
            const std::vector<StripSpec> specs = specs_from(d.surface(), strips);
            stripweave_python::NativeCall release;
            d.set_strips(specs);
          },
          py::arg("strips"), "Each strip as its anchors, (x,y,z) or (x,y,z,dx,dy,dz) in model units")
      .def_property_readonly("strip_count", [](const DesignState& d) { return d.strips().size(); })
      .def("strip", [](const DesignState& d, size_t i) {
        if (i >= d.strips().size()) throw py::index_error("no strip " + std::to_string(i));
        return strip_dict(d.surface(), d.strips()[i]);
      })
      .def("strip_coordinates",
           [](const DesignState& d, size_t i) {
             // Per triangle corner (along, across) in model units; NaN outside the strip.
             if (i >= d.strips().size()) throw py::index_error("no strip " + std::to_string(i));
             const Strip& st = d.strips()[i].strip;
             const py::ssize_t nt = static_cast<py::ssize_t>(st.covered.size());
             py::array_t<double> out({nt, py::ssize_t(3), py::ssize_t(2)});
             auto o = out.mutable_unchecked<3>();
             for (py::ssize_t t = 0; t < nt; ++t)
               for (int c = 0; c < 3; ++c)
                 for (int k = 0; k < 2; ++k) o(t, c, k) = std::nan("");
             for (size_t j = 0; j < st.triangles.size(); ++j)
               for (int c = 0; c < 3; ++c)
                 for (int k = 0; k < 2; ++k) o(st.triangles[j], c, k) = st.coords[j][c][k];
             return out;
           })
      .def("singularities",
           [](const DesignState& d) {
             const Surface& s = d.surface();
             py::list out;
             for (const Singularity& sg : d.field().singularities) {
               py::dict x;
               const Vec3 p = s.similarity.to_model(s.mesh.positions[sg.vertex]);
               x["vertex"] = sg.vertex;
               x["position"] = std::vector<double>{p.x(), p.y(), p.z()};
               x["index"] = sg.index();
               out.append(x);
             }
             return out;
           })
      .def("_fail_solves_for_test", &DesignState::fail_solves_for_test, py::arg("count"),
           "Test entry: the next `count` solves fail as a numerical error would")
      .def_property_readonly("memory_bytes",
                             [](const DesignState& d) {
                               const DesignState::MemoryBytes m = d.memory_bytes();
                               py::dict out;
                               out["strips"] = m.strips;
                               out["field"] = m.field;
                               out["parameterization"] = m.param;
                               out["mask"] = m.mask;
                               out["previous"] = m.previous;
                               return out;
                             })
      .def_property_readonly("fold_overs", [](const DesignState& d) { return d.parameterization().fold_overs; })
      .def_property_readonly("timings_ms",
                             [](const DesignState& d) {
                               py::dict t;
                               t["loops"] = d.timings().loops_ms;
                               t["field"] = d.timings().field_ms;
                               t["parameterization"] = d.timings().param_ms;
                               t["extraction"] = d.timings().extraction_ms;
                               return t;
                             })
      // The parameterization's own steps (cut and comb, energy and
      // constraints, elimination order, KKT system, factorization, solve,
      // output), for profiling.
      .def_property_readonly("parameterization_timings_ms",
                             [](const DesignState& d) {
                               py::dict t;
                               for (const auto& [name, ms] : d.parameterization().timings) t[py::str(name)] = ms;
                               return t;
                             })
      .def_property(
          "compatibility_band",
          [](const DesignState& d) {
            const double b = d.compatibility_band();
            return std::isfinite(b) ? py::object(py::float_(b)) : py::object(py::none());
          },
          [](DesignState& d, py::object band) {
            d.set_compatibility_band(band.is_none() ? std::numeric_limits<double>::infinity()
                                                    : band.cast<double>());
          },
          "How far from its loop (model units) a strip refuses parallel loops; None: the whole strip (paper)")
      .def_property(
          "vertex_pins",
          [](const DesignState& d) {
            std::vector<std::array<double, 3>> out;
            for (const Vec3& p : d.vertex_pins()) {
              const Vec3 x = d.surface().similarity.to_model(p);
              out.push_back({x.x(), x.y(), x.z()});
            }
            return out;
          },
          [](DesignState& d, const std::vector<std::array<double, 3>>& pins) {
            std::vector<Vec3> normalized;
            for (const auto& p : pins) normalized.push_back(d.surface().similarity.to_normalized(Vec3(p[0], p[1], p[2])));
            d.set_vertex_pins(std::move(normalized));
          },
          "Points (model units) where the user put primal vertices (paper §7): each moves its region's vertex there")
      .def_property(
          "edge_routes",
          [](const DesignState& d) {
            std::vector<std::pair<std::array<double, 3>, std::array<double, 3>>> out;
            for (const EdgeRoute& r : d.edge_routes()) {
              const Vec3 t = d.surface().similarity.to_model(r.through), a = d.surface().similarity.to_model(r.across);
              out.push_back({{t.x(), t.y(), t.z()}, {a.x(), a.y(), a.z()}});
            }
            return out;
          },
          [](DesignState& d, const std::vector<std::pair<std::array<double, 3>, std::array<double, 3>>>& routes) {
            std::vector<EdgeRoute> normalized;
            const Similarity& sim = d.surface().similarity;
            for (const auto& [t, a] : routes)
              normalized.push_back({sim.to_normalized(Vec3(t[0], t[1], t[2])), sim.to_normalized(Vec3(a[0], a[1], a[2]))});
            d.set_edge_routes(std::move(normalized));
          },
          "Primal edges routed by hand (paper §7), [(through, across)] in model units: the edge whose arc passes "
          "nearest `across` goes through `through`")
      .def_property(
          "layout_symmetries",
          [](const DesignState& d) {
            py::list out;
            for (const Symmetry& s : d.layout_symmetries()) out.append(symmetry_dict(d.surface(), s));
            return out;
          },
          [](DesignState& d, const std::vector<py::dict>& symmetries) {
            std::vector<Symmetry> normalized;
            for (const py::dict& s : symmetries) normalized.push_back(normalized_symmetry(d.surface(), symmetry_of(s)));
            d.set_layout_symmetries(std::move(normalized));
          },
          "Symmetries (design.md dicts, model units) the layout respects (paper §5.8): regions that are images "
          "of each other get vertices that are images of each other")
      .def_property("compatibility_angle", &DesignState::compatibility_angle, &DesignState::set_compatibility_angle,
                    "Degrees from a strip's direction within which it refuses loops (45: the paper's)")
      .def("disabled_nodes", &DesignState::disabled_nodes)
      .def("apply_mask", &DesignState::apply_mask,
           "Give the session the compatibility mask of every strip, for the next loop");
  bind_layout(m, state);
}

}  // namespace stripweave_python
