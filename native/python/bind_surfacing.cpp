// Bindings of the surfacing stage: patch network -> fitted B-spline patches,
// shell and STEP (surfacing/fit_patch_network.h).
//
// refit(surface, network, tolerance=None, step_path=None, return_brep=False,
//       **options) -> dict
//   network = {"vertices": (V,3) model units,
//              "edges": [{"points": (n,3), "vertices": [i, j],
//                         "sharp": bool, "boundary": bool}],
//              "patches": [{"edges": [4 ints], "reversed": [4 bools],
//                           "vertices": (n,3), "triangles": (m,3),
//                           "corners": [4 ints], "source_face": (m,) (optional),
//                           "even_stretch": bool (optional: its square map
//                           spreads its area evenly, patch_parameterization.h)}]}
//   tolerance: model units (None: 1e-3 of the model's bbox diagonal).
//   progress: an optional Progress: the fit reports its stages to it, and its
//   cancel() stops the fit with Cancelled (FitOptions::progress).
//   Keyword options (FitOptions): relative_tolerance, initial_spans,
//   max_spans, smoothing, seam_weight, seam_mode ('tangent' | 'c1'), tangent_rounds, edge_density, edge_smoothing, parameter_corrections, edge_snap, seam_from,
//   seam_to, crease_angle_deg, vertex_tangent_planes, even_maps, split_patches, max_splits,
//   split_rounds, symmetries (design.md's symmetry dicts, model units: the
//   STEP made exactly symmetric, surfacing/symmetric_fit.h), symmetry_tolerance
//   (model units), deviation_spacing and
//   deviation_chord (model units: how densely the reported deviation is
//   measured, surfacing/fit_deviation.h; 0: the defaults).
//   Returns (lengths in model units; the deviation is two-sided,
//   surfacing/fit_deviation.h):
//     max_deviation, rms_deviation (the larger of both directions),
//     max_deviation_source_to_patches, max_deviation_patches_to_source,
//     rms_deviation_source_to_patches, rms_deviation_patches_to_source,
//     coverage, uncovered_area and source_area (model units^2),
//     source_samples, patch_samples, unsampled_faces, measurement_error,
//     spacing (of the source samples), patch_triangles and patch_chord (the
//     patch tessellation's size and largest chordal error, fit_deviation.h),
//     triangle_uncovered (numpy float array: per Surface triangle, the
//     fraction of its source area not within tolerance of a patch),
//     fit_max_deviation and fit_rms_deviation (the refinement's own measure
//     at its fit samples), per_patch [{max_deviation, rms_deviation,
//     max_deviation_source_to_patch, max_deviation_patch_to_source,
//     rms_deviation_source_to_patch, rms_deviation_patch_to_source,
//     source_area, fit_max_deviation, fit_rms_deviation, nu, nv, samples,
//     worst_uv, side_deviation, crease_deg, crease_edges, crease_length,
//     creased, flipped_fraction, folded, layout_patch (the input patch it
//     is, or a piece of), even_stretch (its square map: even, not
//     harmonic)}] per patch of the fitted network (more than the
//     input's after splits),
//     max_edge_deviation, tolerance, tolerance_met (both directions within
//     tolerance and coverage >= 0.999), creased_patches,
//     folded_patches, max_deviation_uncreased, tolerance_met_uncreased, rounds,
//     splits [{patch, layout_patch, direction ('u': along u = at, 'v'), at,
//     deviation_before, reason, strip, new_patches, closed_strip, round}]
//     (fit_patch_network.h's PatchSplit), rejected_splits (the same, for
//     splits tried and undone: their refit did not help), symmetric, symmetry_error,
//     symmetry_error_fit (None without symmetries or when the layout does not pair; symmetry_problem: why not),
//     uncoupled_patches, max_seam_gap, max_seam_angle_deg (smooth seams,
//     middle of each seam), max_seam_angle_deg_full (whole seam),
//     max_seam_angle_deg_regular (whole seams between valence-4 vertices),
//     max_sharp_angle_deg, smooth_seams, sharp_seams, boundary_edges, faces,
//     shells, free_edges, valid_shell, closed, solids (closed shells made
//     solids, one per input solid of an assembly), volume (None unless closed),
//     shell_tolerance, step_faces_read_back (None without step_path),
//     timings_ms {step: ms}, time_s (the whole call, STEP included), and
//     "brep" (BREP string of the shell) with return_brep=True.
//     With return_patches=True also "patches": per network patch
//     {"nu", "nv", "control": ((nu + 3) * (nv + 3), 3) array, row i along u,
//     index i * (nv + 3) + j} (the uniform clamped bicubic of bspline.h).
//     With return_network=True also "network": the network fitted, in the
//     input's form (the input itself when no even map or split changed it).
//   Runs without the GIL. Bad networks raise InputError.
//
// patch_grid(patch, nu, nv) -> {"uv": (n, 2), "points": (n, 3), "max_chord"}
//   the grid of nu x nv cells the deviation measures on (surfacing/patch_grid.h),
//   node (i, j) at index i * (nv + 1) + j; for tests.
//
// fit_deviation(surface, patches, tolerance, spacing=0, chord=0) -> dict
//   patches as refit's "patches"; the two-sided deviation and coverage of
//   those patches against the surface's source (surfacing/fit_deviation.h):
//   the refit's deviation keys (max_deviation, ..._source_to_patches,
//   ..._patches_to_source, coverage, uncovered_area, source_area,
//   triangle_uncovered, measurement_error, spacing, patch_triangles,
//   patch_chord, per_patch [{max_deviation,
//   max/rms_deviation_source_to_patch, max/rms_deviation_patch_to_source,
//   source_area}]); max_patch_triangles (0: the default) caps the patch
//   tessellation.
//
// square_map(patch) -> ((n, 2) array, gain)
//   patch = {"vertices", "triangles", "corners", "even_stretch" (optional)}
//   as in refit's network: its square map, harmonic or (even_stretch) with
//   its stretch spread evenly, per vertex (surfacing/patch_parameterization.h),
//   and even_map_gain: the harmonic map's largest per-vertex L2 stretch over
//   the even map's. For tests.
//
// cubic_basis(n, t) -> (first, N, dN, d2N)
//   the 4 nonzero cubic basis functions at t of the clamped uniform spline
//   with n spans, their first and second derivatives in t, and the index of
//   the first (surfacing/bspline.h). For tests.
//
// project_to_face(surface, face, points, near=0) -> (n, 3) array
//   the points' foot points on B-rep face `face` of the surface's source
//   (occt/brep_source.h's project_to_face, on a copy of the B-rep of its
//   own): near = 0 each from the face's nearest start-grid sample (the
//   global search where that does not settle); near > 0 in order, each
//   from the previous answer (the refit's warm start); near < 0 each by
//   OCCT's global search alone (the reference). For tests.
// project_to_faces(surface, faces, points, near=0) -> ((n, 3) array, held)
//   the same with point i projected onto face faces[i], all on one copy, and
//   how many of the copy's analysers hold a global-search grid at the end
//   (bounded: occt/brep_source_impl.h). For tests.
#include "bind.h"

#include "stripweave/core/error.h"
#include "stripweave/occt/brep_source.h"
#include "stripweave/surface/surface.h"
#include "stripweave/surfacing/bspline.h"
#include "stripweave/surfacing/fit_patch_network.h"
#include "stripweave/surfacing/patch_grid.h"
#include "stripweave/surfacing/patch_parameterization.h"
#include "stripweave/surfacing/patch_shell.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <chrono>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

namespace {

using ArrayI = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

template <size_t N, typename T>
std::array<T, N> fixed_list(const py::handle& h, const char* what) {
  const auto v = py::cast<std::vector<T>>(h);
  if (v.size() != N) throw InputError(std::string(what) + " must list " + std::to_string(N) + " values");
  std::array<T, N> out;
  std::copy(v.begin(), v.end(), out.begin());
  return out;
}

py::object item(const py::dict& d, const char* key, const char* what) {
  if (!d.contains(key)) throw InputError(std::string(what) + " has no \"" + key + "\"");
  return d[key];
}

// A patch's mesh, corners and map from its dict (network_from's form; the
// edges are left to the caller).
NetworkPatch patch_mesh_from(const py::dict& p) {
  NetworkPatch P;
  P.corners = fixed_list<4, Index>(item(p, "corners", "a patch"), "patch corners");
  P.mesh.positions = points_from(item(p, "vertices", "a patch"), "patch vertices");
  const ArrayI t = py::cast<ArrayI>(item(p, "triangles", "a patch"));
  if (t.ndim() != 2 || t.shape(1) != 3) throw InputError("patch triangles must be an (m, 3) array");
  auto tr = t.unchecked<2>();
  for (py::ssize_t i = 0; i < tr.shape(0); ++i) {
    Tri f{Index(tr(i, 0)), Index(tr(i, 1)), Index(tr(i, 2))};
    for (Index v : f)
      if (v < 0 || v >= P.mesh.num_vertices()) throw InputError("a patch triangle names a vertex that does not exist");
    P.mesh.triangles.push_back(f);
  }
  P.even_stretch = p.contains("even_stretch") && py::cast<bool>(p["even_stretch"]);
  return P;
}

PatchNetwork network_from(const py::dict& net, double diagonal) {
  PatchNetwork n;
  n.bbox_diagonal = diagonal;
  n.vertices = points_from(item(net, "vertices", "network"), "network vertices");
  for (const py::handle& eh : py::cast<py::list>(item(net, "edges", "network"))) {
    const py::dict e = py::cast<py::dict>(eh);
    NetworkEdge E;
    E.points = points_from(item(e, "points", "an edge"), "edge points");
    const auto v = fixed_list<2, Index>(item(e, "vertices", "an edge"), "edge vertices");
    E.v0 = v[0], E.v1 = v[1];
    E.sharp = e.contains("sharp") && py::cast<bool>(e["sharp"]);
    E.boundary = e.contains("boundary") && py::cast<bool>(e["boundary"]);
    n.edges.push_back(std::move(E));
  }
  for (const py::handle& ph : py::cast<py::list>(item(net, "patches", "network"))) {
    const py::dict p = py::cast<py::dict>(ph);
    NetworkPatch P = patch_mesh_from(p);
    P.edges = fixed_list<4, Index>(item(p, "edges", "a patch"), "patch edges");
    P.reversed = fixed_list<4, bool>(item(p, "reversed", "a patch"), "patch reversed");
    if (p.contains("source_face") && !p["source_face"].is_none()) {
      const ArrayI f = py::cast<ArrayI>(p["source_face"]);
      if (f.ndim() != 1 || f.shape(0) != P.mesh.num_triangles())
        throw InputError("patch source_face must hold one face id per triangle");
      auto fr = f.unchecked<1>();
      for (py::ssize_t i = 0; i < fr.shape(0); ++i) P.source_face.push_back(Index(fr(i)));
    }
    n.patches.push_back(std::move(P));
  }
  return n;
}

// A patch as {"nu", "nv", "control": ((nu + 3) * (nv + 3), 3), row i along u}.
BSplinePatch patch_from(const py::handle& h) {
  const py::dict d = py::cast<py::dict>(h);
  BSplinePatch P;
  P.nu = py::cast<int>(item(d, "nu", "a patch"));
  P.nv = py::cast<int>(item(d, "nv", "a patch"));
  if (P.nu < 1 || P.nv < 1) throw InputError("a patch needs at least one span each way");
  P.control = points_from(item(d, "control", "a patch"), "patch control points");
  if (Index(P.control.size()) != Index(P.rows()) * P.cols())
    throw InputError("a patch with nu x nv spans has (nu + 3) * (nv + 3) control points");
  return P;
}

py::dict patch_dict(const BSplinePatch& P) {
  py::array_t<double> control({static_cast<py::ssize_t>(P.control.size()), py::ssize_t(3)});
  auto c = control.mutable_unchecked<2>();
  for (size_t i = 0; i < P.control.size(); ++i)
    for (int j = 0; j < 3; ++j) c(i, j) = P.control[i][j];
  py::dict d;
  d["nu"] = P.nu, d["nv"] = P.nv, d["control"] = control;
  return d;
}

// The fitted network in network_from's form (after splits).
py::dict network_dict(const PatchNetwork& n) {
  py::list edges, patches;
  for (const NetworkEdge& E : n.edges) {
    py::dict e;
    e["points"] = points_array(E.points);
    e["vertices"] = py::make_tuple(E.v0, E.v1);
    e["sharp"] = E.sharp, e["boundary"] = E.boundary;
    edges.append(e);
  }
  for (const NetworkPatch& P : n.patches) {
    py::dict p;
    p["edges"] = P.edges, p["reversed"] = P.reversed, p["corners"] = P.corners, p["even_stretch"] = P.even_stretch;
    p["vertices"] = points_array(P.mesh.positions);
    std::vector<Tri> triangles = P.mesh.triangles;
    p["triangles"] = array_owning<Index>(std::move(triangles), {P.mesh.num_triangles(), py::ssize_t(3)});
    patches.append(p);
  }
  py::dict d;
  d["vertices"] = points_array(n.vertices);
  d["edges"] = edges, d["patches"] = patches;
  return d;
}

py::dict split_dict(const PatchSplit& s) {
  py::dict d;
  d["patch"] = s.patch, d["layout_patch"] = s.layout_patch;
  d["direction"] = s.direction == 0 ? "u" : "v";
  d["at"] = s.at, d["deviation_before"] = s.deviation_before, d["reason"] = s.reason;
  d["strip"] = s.strip, d["new_patches"] = s.new_patches;
  d["closed_strip"] = s.closed_strip, d["round"] = s.round;
  return d;
}

py::array_t<double> double_array(const std::vector<double>& v) {
  return py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
}

// The deviation figures shared by refit and fit_deviation (per_patch aside).
void put_deviation(py::dict& d, const FitDeviation& r) {
  d["max_deviation"] = std::max(r.max_source_to_patches, r.max_patches_to_source);
  d["rms_deviation"] = std::max(r.rms_source_to_patches, r.rms_patches_to_source);
  d["max_deviation_source_to_patches"] = r.max_source_to_patches;
  d["max_deviation_patches_to_source"] = r.max_patches_to_source;
  d["rms_deviation_source_to_patches"] = r.rms_source_to_patches;
  d["rms_deviation_patches_to_source"] = r.rms_patches_to_source;
  d["coverage"] = r.coverage;
  d["uncovered_area"] = r.uncovered_area;
  d["source_area"] = r.source_area;
  d["source_samples"] = r.source_samples;
  d["patch_samples"] = r.patch_samples;
  d["unsampled_faces"] = r.unmeshed_faces;
  d["measurement_error"] = r.measurement_error;
  d["spacing"] = r.spacing;
  d["patch_triangles"] = r.patch_triangles;
  d["patch_chord"] = r.patch_chord;
  d["triangle_uncovered"] = double_array(r.triangle_uncovered);
}

py::dict patch_deviation_dict(const PatchDeviation& f) {
  py::dict p;
  p["max_deviation"] = f.max_deviation();
  p["rms_deviation"] = std::max(f.rms_source_to_patch, f.rms_patch_to_source);
  p["max_deviation_source_to_patch"] = f.max_source_to_patch;
  p["max_deviation_patch_to_source"] = f.max_patch_to_source;
  p["rms_deviation_source_to_patch"] = f.rms_source_to_patch;
  p["rms_deviation_patch_to_source"] = f.rms_patch_to_source;
  p["source_area"] = f.source_area;
  return p;
}

FitOptions options_from(const py::kwargs& kw) {
  FitOptions o;
  for (const auto& [k, v] : kw) {
    const std::string key = py::cast<std::string>(k);
    if (key == "relative_tolerance") o.relative_tolerance = py::cast<double>(v);
    else if (key == "initial_spans") o.initial_spans = py::cast<int>(v);
    else if (key == "max_spans") o.max_spans = py::cast<int>(v);
    else if (key == "smoothing") o.smoothing = py::cast<double>(v);
    else if (key == "seam_weight") o.seam_weight = py::cast<double>(v);
    else if (key == "seam_mode") {
      const std::string m = py::cast<std::string>(v);
      if (m == "tangent") o.seam_mode = 0;
      else if (m == "c1") o.seam_mode = 1;
      else throw InputError("refit: seam_mode is 'tangent' or 'c1'");
    } else if (key == "tangent_rounds") o.tangent_rounds = py::cast<int>(v);
    else if (key == "edge_density") o.edge_density = py::cast<int>(v);
    else if (key == "edge_snap") o.edge_snap = py::cast<double>(v);
    else if (key == "edge_smoothing") o.edge_smoothing = py::cast<double>(v);
    else if (key == "parameter_corrections") o.parameter_corrections = py::cast<int>(v);
    else if (key == "seam_from") o.seam_from = py::cast<double>(v);
    else if (key == "seam_to") o.seam_to = py::cast<double>(v);
    else if (key == "crease_angle_deg") o.crease_angle_deg = py::cast<double>(v);
    else if (key == "vertex_tangent_planes") o.vertex_tangent_planes = py::cast<bool>(v);
    else if (key == "deviation_spacing") o.deviation.spacing = py::cast<double>(v);
    else if (key == "deviation_chord") o.deviation.chord = py::cast<double>(v);
    else if (key == "split_patches") o.split_patches = py::cast<bool>(v);
    else if (key == "even_maps") o.even_maps = py::cast<bool>(v);
    else if (key == "max_splits") o.max_splits = py::cast<int>(v);
    else if (key == "split_rounds") o.split_rounds = py::cast<int>(v);
    else if (key == "symmetries") {
      if (!py::isinstance<py::list>(v) && !py::isinstance<py::tuple>(v))
        throw InputError("refit: symmetries is a list of symmetry dicts");
      for (const auto& d : v) {
        if (!py::isinstance<py::dict>(d)) throw InputError("refit: symmetries is a list of symmetry dicts");
        o.symmetries.push_back(symmetry_of(py::reinterpret_borrow<py::dict>(d)));
      }
    } else if (key == "symmetry_tolerance") o.symmetry_tolerance = py::cast<double>(v);
    else if (key == "progress") o.progress = v.is_none() ? nullptr : py::cast<Progress*>(v);
    else throw InputError("refit: unknown option '" + key + "'");
  }
  return o;
}

}  // namespace

namespace {

// Point i projected onto B-rep face faces[i], all on one copy of the B-rep,
// and how many of the copy's analysers hold a search grid at the end.
std::pair<py::array_t<double>, Index> project_each(const Surface& surface, const std::vector<Index>& faces,
                                                   const py::array_t<double>& points, double near) {
  if (!surface.brep) throw InputError("project_to_face: the surface has no B-rep source");
  const auto x = points.unchecked<2>();
  if (x.shape(1) != 3 || static_cast<size_t>(x.shape(0)) != faces.size())
    throw InputError("project_to_face: points must be (n, 3), one per face");
  for (Index f : faces)
    if (f < 0 || f >= surface.brep->num_faces()) throw InputError("project_to_face: no such face");
  const auto brep = surface.brep->thread_copy();
  std::vector<Vec3> out;
  for (py::ssize_t i = 0; i < x.shape(0); ++i)
    out.push_back(brep->project_to_face(faces[i], Vec3(x(i, 0), x(i, 1), x(i, 2)), nullptr, near));
  return {points_array(std::move(out)), brep->held_search_grids()};
}

}  // namespace

void bind_surfacing(py::module_& m) {
  m.def("cubic_basis", [](int n, double t) {
        if (n < 1) throw InputError("cubic_basis needs at least one span");
        std::array<double, 4> N, dN, d2N;
        const int first = cubic_basis(n, t, N.data(), dN.data(), d2N.data());
        return py::make_tuple(first, N, dN, d2N);
      },
      py::arg("n"), py::arg("t"), "The cubic basis of the clamped uniform spline with n spans at t (for tests)");

  m.def("patch_grid", [](const py::dict& patch, int nu, int nv) {
        PatchGrid g = patch_grid_of_size(patch_from(patch), nu, nv);
        const auto nodes = static_cast<py::ssize_t>(g.uv.size());
        py::dict d;
        d["uv"] = array_owning<double>(std::move(g.uv), {nodes, py::ssize_t(2)});
        d["points"] = points_array(std::move(g.points));
        d["max_chord"] = g.max_chord;
        return d;
      },
      py::arg("patch"), py::arg("nu"), py::arg("nv"),
      "A patch's grid of nu x nv cells (surfacing/patch_grid.h; for tests)");

  m.def("square_map", [](const py::dict& patch) {
        const NetworkPatch P = patch_mesh_from(patch);
        const PatchParameterization map = square_map(P);
        py::array_t<double> uv({static_cast<py::ssize_t>(map.uv.size()), py::ssize_t(2)});
        auto u = uv.mutable_unchecked<2>();
        for (size_t i = 0; i < map.uv.size(); ++i) u(i, 0) = map.uv[i].x(), u(i, 1) = map.uv[i].y();
        return py::make_tuple(uv, even_map_gain(P));
      }, py::arg("patch"));
  m.def("project_to_face", [](const Surface& surface, Index face, const py::array_t<double>& points, double near) {
        return project_each(surface, std::vector<Index>(points.shape(0), face), points, near).first;
      }, py::arg("surface"), py::arg("face"), py::arg("points"), py::arg("near") = 0.0);
  m.def("project_to_faces", [](const Surface& surface, const std::vector<Index>& faces,
                               const py::array_t<double>& points, double near) {
        return project_each(surface, faces, points, near);
      }, py::arg("surface"), py::arg("faces"), py::arg("points"), py::arg("near") = 0.0);
  m.def("refit", [](const Surface& surface, const py::dict& network, std::optional<double> tolerance,
                    std::optional<std::string> step_path, bool return_brep, bool return_patches,
                    bool return_network, const py::kwargs& kw) {
        FitOptions options = options_from(kw);
        if (tolerance) {
          if (!(*tolerance > 0)) throw InputError("refit: the tolerance must be positive");
          options.tolerance = *tolerance;
        }
        const PatchNetwork net = network_from(network, surface.similarity.scale);
        FitResult result;
        Index read_back = -1;
        std::string brep;
        double total_s = 0;
        {
          stripweave_python::NativeCall release;
          const auto start = std::chrono::steady_clock::now();
          result = fit_patch_network(surface, net, options);
          if (step_path) read_back = write_step(result, *step_path);
          if (return_brep && result.shell) brep = to_brep_string(*result.shell);
          total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        }
        const FitReport& r = result.report;
        py::dict d;
        put_deviation(d, r.deviation);
        d["fit_max_deviation"] = r.fit_max_deviation;
        d["fit_rms_deviation"] = r.fit_rms_deviation;
        py::list per_patch;
        for (size_t i = 0; i < r.per_patch.size(); ++i) {
          const PatchFitFigures& f = r.per_patch[i];
          py::dict p = patch_deviation_dict(r.deviation.per_patch[i]);
          p["fit_max_deviation"] = f.fit_max_deviation;
          p["fit_rms_deviation"] = f.fit_rms_deviation;
          p["nu"] = f.nu;
          p["nv"] = f.nv;
          p["samples"] = f.samples;
          p["worst_uv"] = py::make_tuple(f.worst_uv.x(), f.worst_uv.y());
          p["side_deviation"] = f.side_deviation;
          p["crease_deg"] = f.crease_deg;
          p["crease_edges"] = f.crease_edges;
          p["crease_length"] = f.crease_length;
          p["creased"] = f.creased();
          p["flipped_fraction"] = f.flipped_fraction;
          p["folded"] = f.folded();
          p["layout_patch"] = f.layout_patch;
          p["even_stretch"] = f.even_stretch;
          per_patch.append(p);
        }
        d["per_patch"] = per_patch;
        d["max_edge_deviation"] = r.max_edge_deviation;
        d["tolerance"] = r.tolerance;
        d["tolerance_met"] = r.tolerance_met;
        d["creased_patches"] = r.creased_patches;
        d["folded_patches"] = r.folded_patches;
        d["max_deviation_uncreased"] = r.max_deviation_uncreased;
        d["tolerance_met_uncreased"] = r.tolerance_met_uncreased;
        d["rounds"] = r.rounds;
        py::list splits;
        for (const PatchSplit& s : r.splits) splits.append(split_dict(s));
        d["splits"] = splits;
        py::list rejected;
        for (const PatchSplit& s : r.rejected_splits) rejected.append(split_dict(s));
        d["rejected_splits"] = rejected;
        d["uncoupled_patches"] = r.uncoupled_patches;
        if (options.symmetries.empty()) {
          d["symmetric"] = py::none(), d["symmetry_error"] = py::none(), d["symmetry_error_fit"] = py::none();
        } else {
          // Not paired: the fit is left as it is, and there is no image to measure against.
          d["symmetric"] = r.symmetric, d["symmetry_problem"] = r.symmetry_problem;
          d["symmetry_error"] = r.symmetric ? py::object(py::float_(r.symmetry_error)) : py::object(py::none());
          d["symmetry_error_fit"] = r.symmetric ? py::object(py::float_(r.symmetry_error_fit)) : py::object(py::none());
        }
        d["max_seam_gap"] = r.max_seam_gap;
        d["max_seam_angle_deg"] = r.max_seam_angle_deg;
        d["max_seam_angle_deg_full"] = r.max_seam_angle_deg_full;
        d["max_seam_angle_deg_regular"] = r.max_seam_angle_deg_regular;
        d["max_sharp_angle_deg"] = r.max_sharp_angle_deg;
        d["smooth_seams"] = r.smooth_seams;
        d["sharp_seams"] = r.sharp_seams;
        d["boundary_edges"] = r.boundary_edges;
        d["faces"] = r.faces;
        d["shells"] = r.shells;
        d["free_edges"] = r.free_edges;
        d["valid_shell"] = r.valid_shell;
        d["closed"] = r.closed;
        d["solids"] = r.solids;
        d["volume"] = r.closed ? py::object(py::float_(r.volume)) : py::object(py::none());
        d["shell_tolerance"] = r.shell_tolerance;
        d["step_faces_read_back"] = read_back >= 0 ? py::object(py::int_(read_back)) : py::object(py::none());
        py::dict timings;
        for (const auto& [name, ms] : r.timings) timings[py::str(name)] = ms;
        d["timings_ms"] = timings;
        d["time_s"] = total_s;
        if (return_brep) d["brep"] = brep;
        if (return_network) d["network"] = result.network ? py::object(network_dict(*result.network)) : py::object(network);
        if (return_patches) {
          py::list patches;
          for (const BSplinePatch& P : result.surfaces) patches.append(patch_dict(P));
          d["patches"] = patches;
        }
        return d;
      }, py::arg("surface"), py::arg("network"), py::arg("tolerance") = py::none(), py::arg("step_path") = py::none(),
      py::arg("return_brep") = false, py::arg("return_patches") = false, py::arg("return_network") = false,
      "Fit B-spline patches to a quad patch network, sew them, optionally write STEP AP214 (see bind_surfacing.cpp)");

  m.def("fit_deviation", [](const Surface& surface, const py::list& patches, double tolerance, double spacing,
                            double chord, Index max_patch_triangles) {
        if (!(tolerance > 0)) throw InputError("fit_deviation: the tolerance must be positive");
        std::vector<BSplinePatch> P;
        for (const py::handle& h : patches) P.push_back(patch_from(h));
        if (P.empty()) throw InputError("fit_deviation: no patches");
        DeviationOptions options;
        options.spacing = spacing, options.chord = chord;
        if (max_patch_triangles > 0) options.max_patch_triangles = max_patch_triangles;
        FitDeviation r;
        {
          stripweave_python::NativeCall release;
          r = fit_deviation(surface, P, tolerance, options);
        }
        py::dict d;
        put_deviation(d, r);
        py::list per_patch;
        for (const PatchDeviation& f : r.per_patch) per_patch.append(patch_deviation_dict(f));
        d["per_patch"] = per_patch;
        return d;
      }, py::arg("surface"), py::arg("patches"), py::arg("tolerance"), py::arg("spacing") = 0.0,
      py::arg("chord") = 0.0, py::arg("max_patch_triangles") = 0,
      "The two-sided deviation and coverage of B-spline patches against the surface's source (see bind_surfacing.cpp)");
}

}  // namespace stripweave_python
