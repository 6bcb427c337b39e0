// fit_patch_network: the surfacing stage. A primal quad layout
// (PatchNetwork) becomes a watertight network of bicubic B-spline patches
// fitted to the source, sewn into a shell (a solid when closed), with the
// figures that say how good it is.
//
// Input   the Surface (its source B-rep, or its source mesh), the
//         PatchNetwork (model units), FitOptions.
// Output  FitResult: one BSplineCurve3 per network edge, one BSplinePatch
//         per network patch, the sewn OCCT shell (opaque), and FitReport.
// Method
//   1. Harmonic map of each patch mesh onto [0,1]^2 (patch_parameterization.h).
//   2. Samples on the exact source: each patch triangle's vertices, edge
//      midpoints and centroid, projected onto its source_face; each edge's
//      densified polyline projected onto the B-rep (edge_curves.h)
//      (network_samples.h; who neighbours whom: network_topology.h).
//   3. Strips of the layout: opposite sides of a quad must have the same
//      knot vector for neighbours to share control rows, so the span count
//      is a property of a strip (the classes of edges joined by "opposite in
//      a patch": exactly the layout's dual strips). Adaptive refinement: fit
//      every edge curve with its strip's span count, every patch with its
//      boundary rows fixed to the edge curves (patch_fit.h), measure the
//      orthogonal deviation at the samples, and raise the span count of the
//      strips through a patch or edge above tolerance by the cubic
//      convergence estimate n' = n (err/tol)^(1/4), until all meet the
//      tolerance or `max_spans` (steps 3 and 4: network_refinement.h).
//   4. Tangent continuity across the smooth (non-sharp, non-boundary)
//      seams (vertex_tangent_planes, experimental: at a smooth vertex the
//      edge curves leave in the surface's tangent plane there, so the
//      corners share a normal, edge_curves.h); sharp seams stay C0. seam_mode 1 (default): one coupled fit
//      with C1 penalties (A_m - Q_m) + alpha (B_m - Q_m) = 0 (patch_fit.h),
//      which with a constant alpha along the seam is stronger than G1 and
//      costs accuracy where the two patches' parameterizations meet the
//      seam at varying angles. seam_mode 0 (experimental, measured worse
//      on a lofted part: 2.5 deg against 0.02): tangent planes.
//      At each control m of a seam's shared boundary row Q, the normal n_m
//      is the mean of both patches' normals at the Greville point; each
//      patch's first inner control A_m is then pulled to its projection
//      onto the plane through Q_m normal to n_m, and the patches are
//      refitted (tangent_rounds times). When every A_m - Q_m of both sides
//      lies in the plane of n_m, both cross-boundary derivatives and the
//      seam tangent do too: the normals agree (G1) up to the variation of n
//      between Greville points. The conditions are per patch, so the fits
//      stay independent, and they ask nothing a smooth source does not
//      already have. Either way, when the fits without the seam condition
//      meet at a smaller normal angle over the middle of the smooth seams
//      (as on a finely split sphere, 0.7 deg against 1.7), they are kept
//      (uncoupled_patches then counts every patch). Watertightness never depends on this: the boundary rows
//      are the edge curves' control points.
//   5. Report: the two-sided deviation and the coverage (fit_deviation.h:
//      dense samples of the source against every fitted patch, dense samples
//      of every patch against the source), overall and per patch; these are
//      the reported max_deviation, rms_deviation and tolerance_met (both
//      directions within tolerance, coverage at least 0.999). The
//      refinement's own measure (fit_max_deviation, below) is kept for
//      reference: deviation at the samples (orthogonal distance source ->
//      fitted network: the sample's own patch, or, where its foot point
//      falls on the patch border, the nearest of the patches sharing a
//      vertex with it; a layout edge zig-zags over the mesh while its
//      edge curve runs smooth, so a patch-mesh sample by the border may lie
//      on the neighbour's side of the seam), seam gaps (both patches' sides sampled against each
//      other), normal-angle jumps across smooth seams over the middle of
//      each seam ([seam_from, seam_to] of its parameter, since at irregular
//      vertices G1 is impossible at the corner itself) and over the whole
//      seam, per patch why it
//      may miss the tolerance whatever its spans: a crease of the source
//      inside it (patch_creases.h, a layout problem), or a fit that folds
//      (the fitted normal opposes the patch mesh's), and whether the
//      tolerance holds on the patches without creases; then the shell
//      (patch_shell.h).
//   6. Even maps: a patch that still misses the tolerance at max_spans (or
//      the rounds ran out), its own fit samples too, is mapped again with
//      its stretch spread evenly (NetworkPatch::even_stretch,
//      patch_parameterization.h: the harmonic map squashes a protrusion,
//      which evenly spaced knots then cannot resolve), when that could mend
//      it (the largest stretch lowered by g, even_map_gain, and g^4 at
//      least its miss over the tolerance: a bicubic's error goes with the
//      fourth power of the knot spacing), and the network is fitted again. A patch whose own distance (as in the splits, below)
//      did not fall goes back to its harmonic map; the even maps are kept
//      when the patches they helped do not raise the network's largest such
//      distance or fold more patches (or the tolerance is met). Each
//      patch's map is reported (PatchFitFigures::even_stretch).
//   7. Splits: where a patch still misses the tolerance at max_spans (or the
//      rounds ran out), its dual strip is split along an isoline of its
//      square map (split_strip.h) through the worst sample (kept within the
//      middle half), across the direction whose spans are longest on the
//      part, one split per strip and round, and the split network is fitted
//      again (from step 1). A split that did not help (the patch it was
//      made for no closer to the source, or another patch of its strip
//      further than both the tolerance and itself before, each patch by its
//      own distance: fit samples and patch-to-source, not the source a
//      hole leaves nearest to it) is undone, the others refitted without
//      it; a round is kept when the refit meets the tolerance, or every
//      split helped without raising the network's largest such distance or
//      folding more patches; otherwise it is undone and the splitting stops. Every split is reported (FitReport::splits, and the undone
//      ones FitReport::rejected_splits). The refits of one call share their samples:
//      a patch or edge a split did not touch is not projected again
//      (sample_memo.h).
//   8. Symmetry (FitOptions::symmetries, model units; symmetric_fit.h): a
//      strip and its image under each symmetry share one span count, and
//      after the fit each image's control net is the mapped net of its
//      representative (an element that is its own image: its invariant
//      mean), before the report, so the STEP is exactly symmetric; a layout
//      that does not pair is left as fitted (FitReport::symmetric false).
// Errors  InputError for an inconsistent network (a side whose mesh
//         boundary does not carry its edge's polyline, an edge used by more
//         than two patch sides, ...).
#pragma once

#include "stripweave/core/progress.h"

#include "stripweave/core/stopwatch.h"
#include "stripweave/surface/surface.h"
#include "stripweave/surfacing/bspline.h"
#include "stripweave/surfacing/fit_deviation.h"
#include "stripweave/surfacing/patch_network.h"
#include "stripweave/symmetry/symmetry.h"

#include <memory>
#include <string>

namespace stripweave {

class PatchShell;

struct FitOptions {
  double tolerance = 0;              // model units; 0: relative_tolerance * network.bbox_diagonal
  double relative_tolerance = 1e-3;
  int initial_spans = 1;
  int max_spans = 24;
  double smoothing = 1e-9;           // thin-plate weight (against the mean squared data term)
  double seam_weight = 100;          // weight of the seam condition across smooth seams (0: none)
  int seam_mode = 1;                 // 1: C1 coupling, 0: tangent planes (G1 by the averaged normal)
  int tangent_rounds = 2;            // seam_mode 0: rounds of tangent-plane targets
  int edge_density = 4;              // edge polyline segments are split in this many samples
  int parameter_corrections = 0;     // foot-point re-parameterizations per patch fit (experimental: the border
                                     // samples it drops leave the first inner rows free, which can fold)
  double edge_smoothing = 3.0;       // smooth edges: Gaussian sigma in polyline segments (0: none), edge_curves.h
  double edge_snap = 5e-3;           // sharp-edge snap distance, relative to the bbox diagonal
  double seam_from = 0.2, seam_to = 0.8;  // where the seam angle is measured (edge parameter)
  // Edge curves leave smooth vertices in the tangent plane (edge_curves.h).
  // Experimental, off: on handle.step it takes the regular seams from 5.8
  // to 1.6 deg (the corners' normals agree), but on the screw's auto layout
  // it leaves a cusp by one corner of a patch refined to 24 x 24 spans on
  // few samples (179 deg at one seam point, 4.4 without).
  bool vertex_tangent_planes = false;
  double crease_angle_deg = 30;      // a fold of a patch mesh this sharp by a crease lies over it (patch_creases.h)
  bool build_shell = true;
  // Where a patch still misses the tolerance with its spans at max_spans
  // (or the refinement ran out of rounds), its dual strip is split along an
  // isoline of the patch's square map (split_strip.h) and the network is
  // refitted: up to split_rounds times, at most max_splits splits in all.
  bool split_patches = true;
  // Before splitting, such a patch is tried with a square map of even
  // stretch (step 6).
  bool even_maps = true;
  int max_splits = 12;
  int split_rounds = 4;
  // The part's accepted symmetries (model units) and how far a mapped layout
  // vertex or edge midpoint may lie from its image (model units; 0: 1e-3 of
  // the diagonal, the weave's default): step 8.
  std::vector<Symmetry> symmetries;
  double symmetry_tolerance = 0;
  DeviationOptions deviation;        // how the reported deviation is measured (fit_deviation.h)
  // Optional: the stages are reported to it and its cancel() stops the fit
  // (Cancelled is thrown at the next stage or patch, within about a patch's
  // fit): the workbench's Cancel. Not owned.
  Progress* progress = nullptr;
};

// The coverage tolerance_met asks for.
constexpr double kCoverageMet = 0.999;

struct PatchFitFigures {
  // Reported, two-sided (fit_deviation.h): max and RMS the larger of both
  // directions; the source samples nearest to this patch count for it.
  // (each direction in FitReport::deviation.per_patch).
  double max_deviation = 0, rms_deviation = 0;
  // The refinement's own measure: its fit samples against the network.
  double fit_max_deviation = 0, fit_rms_deviation = 0;
  int nu = 0, nv = 0;  // spans
  Index samples = 0;   // fit samples
  Vec2 worst_uv = Vec2::Zero();  // square-map (u, v) of the sample at max_deviation
  double side_deviation = 0;     // largest deviation of its 4 edge curves from their samples
  // Why a patch may miss the tolerance whatever the spans (patch_creases.h):
  // the layout lays it over a crease, or the fitted surface turns its back
  // on the source (area fraction of patch triangles whose normal opposes
  // the fitted surface's normal at their centroid's (u, v)).
  double crease_deg = 0, crease_length = 0;
  Index crease_edges = 0;
  bool over_crease = false;  // crease_length over kCreasedPatchLength of the diagonal (creases.h)
  double flipped_fraction = 0;
  // The input network's patch this one is (a piece of, after splits).
  Index layout_patch = kInvalid;
  bool even_stretch = false;  // its square map spreads its area evenly (step 6), not harmonic
  bool creased() const { return over_crease; }
  bool folded() const { return flipped_fraction > 0; }
};

// A split of a dual strip (split_strip.h), because `patch` missed the
// tolerance at its most spans. Patch indices are the network's at the time
// of the split; a split patch keeps its index for its first piece, so they
// stay valid in the final network (FitResult::network).
struct PatchSplit {
  Index patch = kInvalid;         // the patch that missed
  Index layout_patch = kInvalid;  // the input network's patch it is (a piece of)
  int direction = 0;              // 0: along the isoline u = at (refining u), 1: v = at
  double at = 0.5;
  double deviation_before = 0;    // the patch's deviation when split (model units)
  std::string reason;             // why, in words
  std::vector<Index> strip;       // the patches the split crossed (their first pieces)
  std::vector<Index> new_patches; // their second pieces
  bool closed_strip = false;
  int round = 0;                  // 1 for the splits after the first fit, ...
};

struct FitReport {
  double tolerance = 0;               // model units, as used
  // Reported, two-sided (fit_deviation.h): max_deviation and rms_deviation
  // are the larger of both directions.
  double max_deviation = 0, rms_deviation = 0;
  // Each direction, per patch, the coverage, the uncovered area, per solver
  // triangle its uncovered fraction, how it was measured.
  FitDeviation deviation;
  double fit_max_deviation = 0, fit_rms_deviation = 0;  // the refinement's own measure
  double max_edge_deviation = 0;      // edge curves to their projected samples
  std::vector<PatchFitFigures> per_patch;
  bool tolerance_met = false;         // both directions within tolerance, coverage >= kCoverageMet
  // A trial fit's report (steps 6, 7) whose patches -> source side already
  // misses the tolerance: the source side is not measured (deviation holds
  // the patch side only) unless the trial is kept.
  bool source_side_pending = false;
  // Patches the layout lays over a crease, patches whose fit folds, and
  // whether the tolerance holds on the others (patches and their edges).
  Index creased_patches = 0, folded_patches = 0;
  double max_deviation_uncreased = 0;
  bool tolerance_met_uncreased = false;
  int rounds = 0;                     // refinement rounds (of the last fit)
  std::vector<PatchSplit> splits;     // every split of the network fitted, in order (FitOptions::split_patches)
  // Splits tried and undone: their round's refit did not help (step 7).
  std::vector<PatchSplit> rejected_splits;
  Index uncoupled_patches = 0;        // patches left without the seam coupling (tolerance first)
  double max_seam_gap = 0;            // between neighbouring patches' shared sides
  double max_seam_angle_deg = 0;      // smooth seams, over [seam_from, seam_to]
  double max_seam_angle_deg_full = 0; // smooth seams, whole seam
  double max_seam_angle_deg_regular = 0;  // smooth seams between two regular (valence-4) vertices, whole seam
  double max_sharp_angle_deg = 0;     // largest normal jump over sharp seams (for reference)
  Index smooth_seams = 0, sharp_seams = 0, boundary_edges = 0;
  // The shell (patch_shell.h), when built.
  Index faces = 0, shells = 0, free_edges = 0, solids = 0;
  bool valid_shell = false, closed = false;
  double volume = 0;
  double shell_tolerance = 0;
  // Step 8, with FitOptions::symmetries: whether every symmetry paired the
  // layout (else why not), and the largest distance between an edge's or
  // patch's mapped control points and its image's (model units) as fitted
  // and as returned.
  bool symmetric = false;
  std::string symmetry_problem;
  double symmetry_error_fit = 0, symmetry_error = 0;
  StageTimings timings;  // ms per step
  double time_s = 0;
};

struct FitResult {
  std::vector<BSplineCurve3> edge_curves;  // per network edge, from v0 to v1
  std::vector<BSplinePatch> surfaces;      // per network patch
  FitReport report;
  std::shared_ptr<const PatchShell> shell;  // null unless options.build_shell
  // The network fitted, when even maps or splits changed it (null: the
  // input network).
  std::shared_ptr<const PatchNetwork> network;
};

FitResult fit_patch_network(const Surface& surface, const PatchNetwork& network, const FitOptions& options = {});

// STEP AP214 of the fitted shell (built now if the fit did not build it),
// each patch face named "patch i" and coloured by its deviation over the
// tolerance as deviation.png draws it;
// returns the face count read back from the file.
Index write_step(const FitResult& result, const std::string& path);

}  // namespace stripweave
