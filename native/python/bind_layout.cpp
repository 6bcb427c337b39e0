// Bindings of primalization (paper §7): a design's quad layout.
//
// DesignState.regions(details=False) -> dict
//   The arrangement of the design's loops and its regions, with the design's
//   cross-field singularities (keys: bind_regions.cpp).
// DesignState.layout(details=False) -> dict
//   Everything regions() gives, and the primal quad layout
//   (layout/quad_layout.h) in model units:
//     vertices   [{"position", "valence", "boundary", "region",
//                  "placement" (corner|boundary|feature|singularity|centre|
//                  pinned: moved to one of the design's vertex_pins),
//                  "clearance" (its distance from the loops within its
//                  region), "inradius" (the region's largest),
//                  "image_of" (under the design's layout_symmetries: the
//                  vertex this one is the symmetric image of, None for an
//                  orbit's representative and without symmetries), "pins"
//                  (indices of the design's pins in its region, the last
//                  of which places it)}]
//     edges      [{"points" (n,3), "vertices": [i, j], "arc", "loop",
//                  "sharp", "boundary", "length", "crossing_point" (where
//                  it crosses its arc), "through" (the point of a hand
//                  route, DesignState.edge_routes, it goes through; None),
//                  "route" (the index of the edge route that names the
//                  edge, taken or refused; None)}]
//     patches    [{"edges": [4], "reversed": [4], "corners": [4 vertices],
//                  "corner_angles_deg": [4], "area", "quad", "crease_length"
//                  (creases inside the patch, not on its sides), "creased"
//                  (more than 1% of the diagonal of them)}]; the sides
//                  counter-clockwise seen from outside, side k running from
//                  corner k to corner k + 1
//     summary    {"patches", "irregular_vertices": {valence: n} (inner
//                  vertices of valence != 4), "boundary_vertices": {valence:
//                  n}, "corner_deviation_deg": {"mean", "max"} (|angle - 90|
//                  over the patch corners), "euler": {"V", "E", "F", "chi"}}
//                  Vertices, edges and patches also have "defects": the
//                  kinds of layout_defects.h they show (vertices:
//                  valence2|high_valence, edges: overlapping_edges,
//                  patches: non_quad|overlapping_edges|creased|degenerate);
//                  vertices "forced_valence" (the edges a part corner
//                  there forces, 0 elsewhere), patches "inradius".
//     problems   what keeps the embedding from a clean quad layout
//     crease_conformity  the crease length on primal edges over the whole
//                  crease length (1 without creases); crease_off_edges the
//                  length off them (model units); crease_conforming: no
//                  crease region and at most 1e-6 of the diagonal off them
//     defects    the strict checks' counts: {"non_quad_patches",
//                  "overlapping_edges", "valence2_vertices",
//                  "high_valence_vertices", "creased_patches",
//                  "degenerate_patches", "uncovered_triangles"} (also of an
//                  invalid design: all its surface triangles uncovered)
//     defect_locations  [{"kind", "position" (model units), and "patch",
//                  "vertex", "edges" (the touching pair) or "triangles"
//                  (the uncovered piece's surface triangles)}]
//     layout_ms  primalization alone
//   For an invalid design (a red region) vertices, edges and patches are
//   empty. With details=True also patch_of_triangle (per refined triangle,
//   -1 outside every patch) besides the regions' details.
// layout(session, loops, singular_vertices=[], quarter_indices=[], details=False) -> dict
//   The same for loops of a LoopSession with given singularities (as
//   regions() takes them): a layout of loops that no design's compatibility
//   constrained, e.g. parallel loops of a denser layout.
// DesignState.layout_with(extra_loops, details=False, without=[],
//                         set_aside_red=False) -> dict
//   layout() of the design with these loops added and the loops of the
//   strips `without` (indices) left out, under the design's current
//   singularities (no field or parameterization solve): what automatic
//   weaving predicts a candidate strip, or taking one back, by.
//   set_aside_red: where a region stays red, the layout of the components
//   holding none (layout/set_aside.h), valid if one does.
// DesignState.patch_network(set_aside_red=False) -> the layout as surfacing
//   takes it (surfacing/patch_network.h): {"vertices", "edges": [{"points",
//   "vertices", "sharp", "boundary"}], "patches": [{"edges", "reversed",
//   "vertices", "triangles", "corners", "source_face"}], "bbox_diagonal"};
//   set_aside_red as for layout_with.
#include "bind_regions.h"

#include "stripweave/layout/patch_network_of.h"
#include "stripweave/strips/design_state.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

namespace {

const char* placement_name(VertexPlacement p) {
  switch (p) {
    case VertexPlacement::Corner: return "corner";
    case VertexPlacement::Boundary: return "boundary";
    case VertexPlacement::Feature: return "feature";
    case VertexPlacement::Singularity: return "singularity";
    case VertexPlacement::Centre: return "centre";
    case VertexPlacement::Pinned: return "pinned";
  }
  return "centre";
}

std::vector<std::string> kind_names(const std::vector<DefectKind>& kinds) {
  std::vector<std::string> out;
  for (DefectKind k : kinds) out.push_back(defect_name(k));
  return out;
}

py::dict defect_counts(const LayoutDefects& D) {
  py::dict d;
  d["non_quad_patches"] = D.non_quad_patches;
  d["overlapping_edges"] = D.overlapping_edges;
  d["valence2_vertices"] = D.valence2_vertices;
  d["high_valence_vertices"] = D.high_valence_vertices;
  d["creased_patches"] = D.creased_patches;
  d["degenerate_patches"] = D.degenerate_patches;
  d["uncovered_triangles"] = D.uncovered_triangles;
  return d;
}

py::list defect_locations(const LayoutDefects& D) {
  py::list out;
  for (const DefectLocation& x : D.locations) {
    py::dict d;
    d["kind"] = defect_name(x.kind);
    d["position"] = std::vector<double>{x.position.x(), x.position.y(), x.position.z()};
    if (x.patch != kInvalid) d["patch"] = x.patch;
    if (x.vertex != kInvalid) d["vertex"] = x.vertex;
    if (x.edge != kInvalid) d["edges"] = std::vector<Index>{x.edge, x.other_edge};
    if (x.kind == DefectKind::Uncovered) d["triangles"] = x.triangles;
    out.append(d);
  }
  return out;
}

using DesignLayout = LoopLayout;

// The design's loops (their embedded paths, kept with the strips) but those
// of the strips `without`, and `extra` loops, laid out under the design's
// singularities, pins, symmetries and edge routes (layout/loop_layout.h).
DesignLayout design_layout(const DesignState& d, bool primal, const std::vector<Loop>& extra = {},
                           const std::vector<Index>& without = {}, bool set_aside_red = false) {
  std::vector<LoopPath> paths;
  for (size_t i = 0; i < d.strips().size(); ++i)
    if (std::find(without.begin(), without.end(), static_cast<Index>(i)) == without.end())
      paths.push_back(d.strips()[i].path);
  for (const Loop& loop : extra) paths.push_back(loop_path(d.session(), loop));
  return layout_loops(d.surface(), paths, d.field().singularities, primal, d.vertex_pins(), d.layout_symmetries(),
                      d.edge_routes(), set_aside_red);
}

py::dict layout_dict(const Surface& s, const std::vector<Singularity>& singular, const DesignLayout& dl,
                     bool details) {
  const QuadLayout& L = dl.layout;
  const LoopArrangement& A = dl.computed.arrangement;
  const Similarity& sim = s.similarity;
  py::dict out = regions_dict(s, singular, dl.computed, details);

  py::list vertices;
  std::map<int, int> irregular, boundary_valence;
  for (const PrimalVertex& v : L.vertices) {
    py::dict d;
    const Vec3 p = sim.to_model(v.position);
    d["position"] = std::vector<double>{p.x(), p.y(), p.z()};
    d["valence"] = v.valence;
    d["boundary"] = v.boundary;
    d["region"] = v.region;
    d["placement"] = placement_name(v.placement);
    d["image_of"] = v.image_of == kInvalid ? py::object(py::none()) : py::object(py::int_(v.image_of));
    d["pins"] = v.pins;
    d["clearance"] = v.clearance * sim.scale;
    d["inradius"] = v.inradius * sim.scale;
    d["defects"] = kind_names(L.defects.vertex_defects[vertices.size()]);
    d["forced_valence"] = L.defects.vertex_forced_valence[vertices.size()];
    vertices.append(d);
    if (v.boundary) ++boundary_valence[v.valence];
    else if (v.valence != 4) ++irregular[v.valence];
  }
  py::list edges;
  for (const PrimalEdge& e : L.edges) {
    std::vector<Vec3> pts;
    for (Index v : e.path) pts.push_back(sim.to_model(L.positions[v]));
    py::dict d;
    d["points"] = points_array(pts);
    d["vertices"] = std::vector<Index>{e.v0, e.v1};
    d["arc"] = e.arc;
    d["loop"] = A.arcs[e.arc].loop;
    d["sharp"] = e.sharp;
    d["boundary"] = e.boundary;
    d["length"] = e.length * sim.scale;
    const Vec3 c = sim.to_model(L.positions[e.path[e.crossing]]);
    d["crossing_point"] = std::vector<double>{c.x(), c.y(), c.z()};
    if (e.through == kInvalid) {
      d["through"] = py::none();
    } else {
      const Vec3 t = sim.to_model(L.positions[e.through]);
      d["through"] = std::vector<double>{t.x(), t.y(), t.z()};
    }
    d["route"] = e.route == kInvalid ? py::object(py::none()) : py::object(py::int_(e.route));
    d["defects"] = kind_names(L.defects.edge_defects[edges.size()]);
    edges.append(d);
  }
  py::list patches;
  double deviation_sum = 0, deviation_max = 0;
  int corners = 0;
  for (const PrimalPatch& p : L.patches) {
    py::dict d;
    d["edges"] = std::vector<Index>(p.edges.begin(), p.edges.end());
    d["reversed"] = std::vector<bool>(p.reversed.begin(), p.reversed.end());
    d["corners"] = std::vector<Index>(p.corners.begin(), p.corners.end());
    std::vector<double> angles;
    if (p.quad) {
      for (double a : p.corner_angle) {
        const double deg = a * 180.0 / M_PI;
        angles.push_back(deg);
        deviation_sum += std::abs(deg - 90.0);
        deviation_max = std::max(deviation_max, std::abs(deg - 90.0));
        ++corners;
      }
    }
    d["corner_angles_deg"] = angles;
    d["area"] = p.area * sim.scale * sim.scale;
    d["quad"] = p.quad;
    d["crease_length"] = p.crease_length * sim.scale;
    d["creased"] = p.creased();
    d["inradius"] = L.defects.patch_inradius[patches.size()] * sim.scale;
    d["defects"] = kind_names(L.defects.patch_defects[patches.size()]);
    patches.append(d);
  }
  auto counts = [](const std::map<int, int>& m) {
    py::dict d;
    for (const auto& [valence, n] : m) d[py::str(std::to_string(valence))] = n;
    return d;
  };
  const Index V = static_cast<Index>(L.vertices.size()), E = static_cast<Index>(L.edges.size()),
              F = static_cast<Index>(L.patches.size());
  py::dict summary, deviation, euler;
  deviation["mean"] = corners ? deviation_sum / corners : 0.0;
  deviation["max"] = deviation_max;
  euler["V"] = V, euler["E"] = E, euler["F"] = F;
  euler["chi"] = s.mesh.num_vertices() - s.topology.num_edges() + s.mesh.num_triangles();
  summary["patches"] = F;
  summary["irregular_vertices"] = counts(irregular);
  summary["boundary_vertices"] = counts(boundary_valence);
  summary["corner_deviation_deg"] = deviation;
  summary["euler"] = euler;
  out["vertices"] = vertices;
  out["edges"] = edges;
  out["patches"] = patches;
  out["summary"] = summary;
  out["problems"] = L.problems;
  out["crease_conformity"] = L.crease_conformity;
  out["crease_off_edges"] = L.crease_off_edges * sim.scale;
  out["crease_conforming"] = L.crease_conforming;
  out["defects"] = defect_counts(L.defects);
  out["defect_locations"] = defect_locations(L.defects);
  out["layout_ms"] = dl.layout_ms;
  if (details) out["patch_of_triangle"] = L.triangle_patch;
  return out;
}

py::dict network_dict(const PatchNetwork& net) {
  py::list edges, patches;
  for (const NetworkEdge& e : net.edges) {
    py::dict d;
    d["points"] = points_array(e.points);
    d["vertices"] = std::vector<Index>{e.v0, e.v1};
    d["sharp"] = e.sharp;
    d["boundary"] = e.boundary;
    edges.append(d);
  }
  for (const NetworkPatch& p : net.patches) {
    py::dict d;
    d["edges"] = std::vector<Index>(p.edges.begin(), p.edges.end());
    d["reversed"] = std::vector<bool>(p.reversed.begin(), p.reversed.end());
    d["vertices"] = points_array(p.mesh.positions);
    py::array_t<std::int32_t> tris({static_cast<py::ssize_t>(p.mesh.num_triangles()), py::ssize_t(3)});
    auto o = tris.mutable_unchecked<2>();
    for (Index t = 0; t < p.mesh.num_triangles(); ++t)
      for (int j = 0; j < 3; ++j) o(t, j) = p.mesh.triangles[t][j];
    d["triangles"] = tris;
    d["corners"] = std::vector<Index>(p.corners.begin(), p.corners.end());
    d["source_face"] = p.source_face;
    patches.append(d);
  }
  py::dict out;
  out["vertices"] = points_array(net.vertices);
  out["edges"] = edges;
  out["patches"] = patches;
  out["bbox_diagonal"] = net.bbox_diagonal;
  return out;
}

}  // namespace

void bind_layout(py::module_& m, py::class_<DesignState, std::shared_ptr<DesignState>>& state) {
  m.def(
      "layout",
      [](const LoopSession& session, const std::vector<Loop>& loops, const std::vector<Index>& singular_vertices,
         const std::vector<int>& quarter_indices, bool details) {
        const Surface& s = session.surface();
        const std::vector<Singularity> singular = singularities_from(s, singular_vertices, quarter_indices);
        DesignLayout dl;
        {
          stripweave_python::NativeCall release;
          std::vector<LoopPath> paths = embed_loops(session, loops);
          dl = layout_loops(s, paths, singular, true);
        }
        return layout_dict(s, singular, dl, details);
      },
      py::arg("session"), py::arg("loops"), py::arg("singular_vertices") = std::vector<Index>(),
      py::arg("quarter_indices") = std::vector<int>(), py::arg("details") = false,
      "The regions and primal quad layout of loops (paper §7; model units)");
  m.def(
      "layout_of_paths",
      [](const Surface& s, const std::vector<py::dict>& paths, const std::vector<Index>& singular_vertices,
         const std::vector<int>& quarter_indices, bool details) {
        const std::vector<Singularity> singular = singularities_from(s, singular_vertices, quarter_indices);
        std::vector<LoopPath> loops = paths_from_dicts(s, paths);
        DesignLayout dl;
        {
          stripweave_python::NativeCall release;
          dl = layout_loops(s, loops, singular, true);
        }
        return layout_dict(s, singular, dl, details);
      },
      py::arg("surface"), py::arg("paths"), py::arg("singular_vertices") = std::vector<Index>(),
      py::arg("quarter_indices") = std::vector<int>(), py::arg("details") = false,
      "layout() for loops given as embedded paths (as regions_of_paths; for tests and tools)");
  m.def(
      "network_of_paths",
      [](const Surface& s, const std::vector<py::dict>& paths) {
        std::vector<LoopPath> loops = paths_from_dicts(s, paths);
        PatchNetwork net;
        {
          stripweave_python::NativeCall release;
          const DesignLayout dl = layout_loops(s, loops, {}, true);
          net = patch_network_of(s, dl.computed.arrangement, dl.layout);
        }
        return network_dict(net);
      },
      py::arg("surface"), py::arg("paths"),
      "The patch network (as DesignState.patch_network) of loops given as embedded paths (for tests)");
  state.def(
      "layout_with",
      [](const DesignState& d, const std::vector<Loop>& extra, bool details, const std::vector<Index>& without,
         bool set_aside_red) {
        DesignLayout dl;
        {
          stripweave_python::NativeCall release;
          dl = design_layout(d, true, extra, without, set_aside_red);
        }
        return layout_dict(d.surface(), d.field().singularities, dl, details);
      },
      py::arg("extra_loops"), py::arg("details") = false, py::arg("without") = std::vector<Index>(),
      py::arg("set_aside_red") = false,
      "The layout the design would have with these loops added and the strips `without` left out, under its "
      "current singularities (no solve); the same as layout(session, design loops but those + extra_loops, the "
      "design's singularities), without embedding the design's loops again");
  state.def(
      "regions",
      [](const DesignState& d, bool details) {
        DesignLayout dl;
        {
          stripweave_python::NativeCall release;
          dl = design_layout(d, false);
        }
        return regions_dict(d.surface(), d.field().singularities, dl.computed, details);
      },
      py::arg("details") = false, "The arrangement of the design's loops and its regions (paper §4.2)");
  state.def(
      "layout",
      [](const DesignState& d, bool details) {
        DesignLayout dl;
        {
          stripweave_python::NativeCall release;
          dl = design_layout(d, true);
        }
        return layout_dict(d.surface(), d.field().singularities, dl, details);
      },
      py::arg("details") = false, "The design's regions and primal quad layout (paper §7)");
  state.def(
      "patch_network",
      [](const DesignState& d, bool set_aside_red) {
        PatchNetwork net;
        Index layout_patches = 0;
        {
          stripweave_python::NativeCall release;
          const DesignLayout dl = design_layout(d, true, {}, {}, set_aside_red);
          net = patch_network_of(d.surface(), dl.computed.arrangement, dl.layout);
          layout_patches = static_cast<Index>(dl.layout.patches.size());
        }
        py::dict out = network_dict(net);
        // The layout's patch count: those that are not clean quads are left
        // out of the network, and the refit reports how many.
        out["layout_patches"] = layout_patches;
        return out;
      },
      py::arg("set_aside_red") = false,
      "The quad layout as the surfacing stage takes it (model units), with layout_patches");
}

}  // namespace stripweave_python
