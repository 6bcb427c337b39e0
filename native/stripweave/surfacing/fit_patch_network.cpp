#include "stripweave/surfacing/fit_patch_network.h"

#include "stripweave/core/error.h"
#include "stripweave/surface/creases.h"
#include "stripweave/surfacing/edge_curves.h"
#include "stripweave/surfacing/fit_deviation.h"
#include "stripweave/surfacing/network_refinement.h"
#include "stripweave/surfacing/network_samples.h"
#include "stripweave/surfacing/network_topology.h"
#include "stripweave/surfacing/patch_creases.h"
#include "stripweave/surfacing/patch_fit.h"
#include "stripweave/surfacing/patch_parameterization.h"
#include "stripweave/surfacing/patch_shell.h"
#include "stripweave/surfacing/sample_memo.h"
#include "stripweave/surfacing/source_projection.h"
#include "stripweave/surfacing/split_strip.h"
#include "stripweave/surfacing/symmetric_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>

namespace stripweave {

namespace {

// Step 1: the square map of each patch mesh onto the unit square, its
// sides checked against their edges' polylines.
std::vector<PatchParameterization> parameterize_patches(const PatchNetwork& network) {
  const Index nP = static_cast<Index>(network.patches.size());
  std::vector<PatchParameterization> param(nP);
  for (Index p = 0; p < nP; ++p) {
    try {
      param[p] = square_map(network.patches[p]);
    } catch (const InputError& e) {
      throw InputError("patch " + std::to_string(p) + ": " + e.what());
    }
    for (int s = 0; s < 4; ++s) {
      const NetworkEdge& E = network.edges[network.patches[p].edges[s]];
      if (param[p].side_vertices[s].size() != E.points.size())
        throw InputError(side_name(p, s) + " has " + std::to_string(param[p].side_vertices[s].size()) +
                         " boundary points in the patch mesh but its edge polyline has " +
                         std::to_string(E.points.size()));
    }
  }
  return param;
}

// Step 8: each image's control net becomes the mapped net of its
// representative (symmetric_fit.h), and the refinement's measure is taken
// again on the symmetric nets.
void symmetrize(const PatchNetwork& network, const NetworkTopology& topology,
                const std::vector<NetworkPairing>& pairings, const NetworkSamples& samples, const FitOptions& options,
                double diag, FitResult& result, std::vector<double>& edge_dev) {
  FitReport& report = result.report;
  report.symmetric = std::all_of(pairings.begin(), pairings.end(), [](const NetworkPairing& p) { return p.paired; });
  FitNets nets{std::move(result.edge_curves), std::move(result.surfaces)};
  report.symmetry_error_fit = symmetry_error(nets, network, options.symmetries, pairings);
  report.symmetry_error = symmetrize_fit(nets, network, options.symmetries, pairings, diag);
  result.edge_curves = std::move(nets.edges);
  result.surfaces = std::move(nets.patches);
  for (Index e = 0; e < Index(network.edges.size()); ++e)
    edge_dev[e] = edge_curve_deviation(result.edge_curves[e], samples.edges[e]);
  std::vector<Index> all(network.patches.size());
  std::iota(all.begin(), all.end(), 0);
  measure_patch_fits(result.surfaces, all, topology, samples.patches, report.tolerance, report.per_patch);
}

// Per patch: its edge curves' deviation, the part's creases under it (the
// surface's one crease set) and where the fit turns its back on the source
// (patch_creases.h: the area fraction of patch-mesh triangles whose normal
// opposes the fitted normal at their centroid's (u, v)).
void report_creases_and_folds(const Surface& surface, const PatchNetwork& network, const NetworkSamples& samples,
                              const std::vector<double>& edge_dev, const FitOptions& options, double diag,
                              FitResult& result) {
  FitReport& report = result.report;
  const SegmentLocator creases = crease_locator(surface);
  const CreaseTest crease_test{options.crease_angle_deg, 1e-6 * diag};
  for (Index p = 0; p < Index(network.patches.size()); ++p) {
    const NetworkPatch& P = network.patches[p];
    PatchFitFigures& f = report.per_patch[p];
    for (Index e : P.edges) f.side_deviation = std::max(f.side_deviation, edge_dev[e]);
    const PatchCreases c = patch_creases(P.mesh, creases, crease_test);
    f.crease_deg = c.max_dihedral_deg, f.crease_edges = c.crease_edges, f.crease_length = c.crease_length;
    f.over_crease = c.crease_length > kCreasedPatchLength * diag;
    // Centroid samples follow the vertex samples, one per triangle.
    const TriangleMesh& m = samples.mesh(network, p);
    const Index nv = m.num_vertices();
    const std::vector<Vec2>& uv = samples.patches[p].uv;
    double flipped = 0, area = 0;
    for (Index t = 0; t < m.num_triangles() && nv + t < Index(uv.size()); ++t) {
      const Vec3 n = triangle_normal_area2(m, t);
      area += n.norm();
      if (result.surfaces[p].normal(uv[nv + t].x(), uv[nv + t].y()).dot(n) < 0) flipped += n.norm();
    }
    f.flipped_fraction = area > 0 ? flipped / area : 0;
    report.creased_patches += f.creased();
    report.folded_patches += f.folded();
  }
}

// The refinement's own measure over the network (at the fit samples), for
// reference, and the edge curves' largest deviation (edges no patch uses,
// whose patches were left out of the network, say nothing of the shell).
void report_refinement_measure(const NetworkTopology& topology, const std::vector<double>& edge_dev,
                               FitReport& report) {
  double sum2 = 0;
  Index count = 0;
  for (const PatchFitFigures& f : report.per_patch) {
    report.fit_max_deviation = std::max(report.fit_max_deviation, f.fit_max_deviation);
    sum2 += f.fit_rms_deviation * f.fit_rms_deviation * f.samples;
    count += f.samples;
  }
  report.fit_rms_deviation = count ? std::sqrt(sum2 / count) : 0;
  for (Index e = 0; e < Index(edge_dev.size()); ++e)
    if (!topology.uses[e].empty()) report.max_edge_deviation = std::max(report.max_edge_deviation, edge_dev[e]);
}

// The seams, densely: the gap between both patches' sides everywhere, and
// the normal jump over sharp seams (for reference) and smooth ones (whole,
// middle, and between two regular vertices, where exactly 4 smooth seams
// meet).
void measure_seams(const PatchNetwork& network, const NetworkTopology& topology,
                   const std::vector<BSplinePatch>& surfaces, const FitOptions& options, FitReport& report) {
  const Index nE = static_cast<Index>(network.edges.size());
  std::vector<Index> valence(network.vertices.size(), 0);
  std::vector<bool> regular(network.vertices.size(), true);
  for (Index e = 0; e < nE; ++e)
    for (Index v : {network.edges[e].v0, network.edges[e].v1}) {
      ++valence[v];
      if (network.edges[e].sharp || network.edges[e].boundary || topology.uses[e].size() != 2) regular[v] = false;
    }
  constexpr int kSeamSamples = 41;
  for (Index e = 0; e < nE; ++e) {
    if (topology.uses[e].size() != 2) continue;
    const NetworkEdge& E = network.edges[e];
    const SideUse &a = topology.uses[e][0], &b = topology.uses[e][1];
    const BSplinePatch &A = surfaces[a.patch], &B = surfaces[b.patch];
    const bool between_regular = regular[E.v0] && valence[E.v0] == 4 && regular[E.v1] && valence[E.v1] == 4;
    for (int k = 0; k < kSeamSamples; ++k) {
      const double t = double(k) / (kSeamSamples - 1);  // along the edge, from v0
      const Vec2 ua = side_uv(a.side, a.reversed ? 1 - t : t);
      const Vec2 ub = side_uv(b.side, b.reversed ? 1 - t : t);
      report.max_seam_gap = std::max(report.max_seam_gap, (A.value(ua.x(), ua.y()) - B.value(ub.x(), ub.y())).norm());
      if (k == 0 || k == kSeamSamples - 1) continue;
      const double angle = normal_jump_deg(A.normal(ua.x(), ua.y()), B.normal(ub.x(), ub.y()));
      if (E.sharp || E.boundary) {
        report.max_sharp_angle_deg = std::max(report.max_sharp_angle_deg, angle);
        continue;
      }
      report.max_seam_angle_deg_full = std::max(report.max_seam_angle_deg_full, angle);
      if (t >= options.seam_from - 1e-12 && t <= options.seam_to + 1e-12)
        report.max_seam_angle_deg = std::max(report.max_seam_angle_deg, angle);
      if (between_regular) report.max_seam_angle_deg_regular = std::max(report.max_seam_angle_deg_regular, angle);
    }
  }
}

// The report's figures from its two-sided deviation.
void report_figures(const std::vector<BSplinePatch>& surfaces, FitReport& report) {
  const double tol = report.tolerance;
  const FitDeviation& dev = report.deviation;
  double uncreased_edges = 0;
  for (size_t p = 0; p < surfaces.size(); ++p) {
    PatchFitFigures& f = report.per_patch[p];
    const PatchDeviation& d = dev.per_patch[p];
    f.max_deviation = d.max_deviation();
    f.rms_deviation = std::max(d.rms_source_to_patch, d.rms_patch_to_source);
    if (f.creased()) continue;
    report.max_deviation_uncreased = std::max(report.max_deviation_uncreased, f.max_deviation);
    uncreased_edges = std::max(uncreased_edges, f.side_deviation);
  }
  report.max_deviation = std::max(dev.max_source_to_patches, dev.max_patches_to_source);
  report.rms_deviation = std::max(dev.rms_source_to_patches, dev.rms_patches_to_source);
  for (const auto& [name, ms] : dev.timings) report.timings.emplace_back("deviation_" + name, ms);
  report.tolerance_met = report.max_deviation <= tol && dev.coverage >= kCoverageMet;
  report.tolerance_met_uncreased = report.max_deviation_uncreased <= tol && uncreased_edges <= tol;
  report.source_side_pending = false;
}

// The reported figures: the two-sided deviation and the coverage
// (fit_deviation.h), overall and per patch; the tolerance is met when both
// directions are within it and the patches cover the source.
// A trial fit (`trial`: an even map or a split, steps 6 and 7) is judged by
// each patch's own distance (patch_own_miss: its fit samples and the patches
// -> source side) and by tolerance_met, which no source side can make true
// while a patch lies farther than the tolerance from the source: then only
// that side is measured (the source side, half the measurement's time, is
// of no use to a trial that is undone) and source_side_pending is set;
// complete_deviation adds the source side if the trial is kept.
void report_deviation(const Surface& surface, const std::vector<BSplinePatch>& surfaces, const FitOptions& options,
                      FitReport& report, bool trial) {
  const double tol = report.tolerance;
  FitDeviation& dev = report.deviation;
  if (!trial) {
    dev = fit_deviation(surface, surfaces, tol, options.deviation);
  } else {
    dev = patches_to_source_deviation(surface, surfaces, tol, options.deviation);
    if (dev.max_patches_to_source > tol) {
      report.source_side_pending = true;
      report.tolerance_met = false;
      return;
    }
    add_source_side(surface, surfaces, tol, options.deviation, dev);
  }
  report_figures(surfaces, report);
}

// A kept trial's report, both sides measured: exactly what the fit would
// have reported as the first fit (the two sides are independent figures of
// the patches alone), its patches -> source side not measured again.
void complete_deviation(const Surface& surface, const FitOptions& options, FitResult& result) {
  FitReport& report = result.report;
  if (!report.source_side_pending) return;
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  add_source_side(surface, result.surfaces, report.tolerance, options.deviation, report.deviation);
  report_figures(result.surfaces, report);
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  report.timings.emplace_back("deviation_completed", ms);
  report.time_s += 1e-3 * ms;
}

// Steps 1 to 5 (the header) and 7 on one network, without the shell.
// `memo`: the samples of the fits before (sample_memo.h); `trial`: see
// report_deviation.
FitResult fit_network(const Surface& surface, const PatchNetwork& network, const FitOptions& options,
                      SampleMemo& memo, bool trial = false) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  FitResult result;
  FitReport& report = result.report;
  Stopwatch watch(report.timings);
  if (network.patches.empty()) throw InputError("the patch network has no patches");
  const double diag = network.bbox_diagonal > 0 ? network.bbox_diagonal : 1.0;
  report.tolerance = options.tolerance > 0 ? options.tolerance : options.relative_tolerance * diag;
  // Stages for the GUI's progress; Cancelled from a cancel() (FitOptions::progress).
  auto stage = [&](const char* name, double begin, double end) {
    if (options.progress) options.progress->stage(name, begin, end);
  };
  stage("parameterizing the patches", 0.0, 0.1);
  const NetworkTopology topology = network_topology(network);
  std::vector<NetworkPairing> pairings;  // step 8: the layout's images under each symmetry
  const double symmetry_tol = options.symmetry_tolerance > 0 ? options.symmetry_tolerance : 1e-3 * diag;
  for (const Symmetry& psi : options.symmetries) {
    pairings.push_back(pair_network(network, psi, symmetry_tol));
    if (!pairings.back().paired && report.symmetry_problem.empty()) report.symmetry_problem = pairings.back().problem;
  }
  std::vector<PatchParameterization> param = parameterize_patches(network);
  watch.lap("parameterize");

  stage("sampling the source", 0.1, 0.3);
  const SourceProjector projector(surface, options.edge_snap * diag);
  NetworkSamples samples = sample_network(network, topology, param, projector, options, memo);
  watch.lap("sample");

  stage("fitting B-spline patches", 0.3, 0.6);
  const std::vector<Vec3> vertex_normal = options.vertex_tangent_planes
                                              ? smooth_vertex_normals(network, topology, samples, projector)
                                              : std::vector<Vec3>(network.vertices.size(), Vec3::Zero());
  std::vector<double> edge_dev =
      refine_network_fit(network, topology, pairings, samples.edges, samples.patches, vertex_normal, options, result);
  watch.lap("fit");
  stage("reporting", 0.6, 0.62);
  if (!pairings.empty()) {
    symmetrize(network, topology, pairings, samples, options, diag, result, edge_dev);
    watch.lap("symmetry");
  }
  report_creases_and_folds(surface, network, samples, edge_dev, options, diag, result);
  report_refinement_measure(topology, edge_dev, report);
  watch.lap("report");

  stage("measuring the deviation both ways", 0.62, 0.9);
  // The fit's own samples are done with: freed before the deviation builds
  // its tessellations and trees, the peak of the surfacing stage.
  std::vector<PatchSamples>().swap(samples.patches);
  std::vector<EdgeSamples>().swap(samples.edges);
  report_deviation(surface, result.surfaces, options, report, trial);
  watch.lap("deviation");
  stage("measuring the seams", 0.9, 0.93);
  measure_seams(network, topology, result.surfaces, options, report);
  watch.lap("measure");
  report.time_s = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

double polyline_length(const std::vector<Vec3>& points) {
  double length = 0;
  for (size_t k = 1; k < points.size(); ++k) length += (points[k] - points[k - 1]).norm();
  return length;
}

// How far a patch misses: the reported two-sided deviation, or the
// refinement's own measure at its fit samples.
double patch_miss(const PatchFitFigures& f) { return std::max(f.max_deviation, f.fit_max_deviation); }

// Whether a patch misses the tolerance with its spans run out (or the
// refinement's rounds), its own fit samples too, over no crease: what an
// even map (step 6) or a split (step 7) may mend. A patch over a crease is
// left alone (a layout problem: the strips should run along the crease).
// A patch whose own fit samples all lie within tolerance misses between
// them or across a seam: a cut through its worst sample would be placed
// blind, and every such trial costs a full refit (the corpus: 8 of 8
// splits undone on a casting, the fit's peak memory doubled).
bool mendable_miss(const PatchFitFigures& f, const FitReport& report, const FitOptions& options) {
  const double tol = report.tolerance;
  const bool saturated = f.nu >= options.max_spans || f.nv >= options.max_spans;
  if (f.fit_max_deviation <= tol || patch_miss(f) <= tol || f.creased()) return false;
  return saturated || report.rounds >= kMaxRefinementRounds;
}

// A patch whose strip is to be split (step 7), and why.
struct SplitChoice {
  StripCut cut;
  double deviation = 0;
  std::string reason;
};

// The mendable misses, worst first. The cut refines the saturated
// direction, or, both saturated, the one whose spans are longer on the
// part; it runs through the worst sample, kept within the middle half of
// the patch so that both pieces get a fair share of it.
std::vector<SplitChoice> split_choices(const PatchNetwork& net, const FitReport& report, const FitOptions& options) {
  std::vector<SplitChoice> out;
  const double tol = report.tolerance;
  const bool rounds_out = report.rounds >= kMaxRefinementRounds;
  for (Index p = 0; p < Index(net.patches.size()); ++p) {
    const PatchFitFigures& f = report.per_patch[p];
    const double deviation = patch_miss(f);
    const bool saturated[2] = {f.nu >= options.max_spans, f.nv >= options.max_spans};
    if (!mendable_miss(f, report, options)) continue;
    const NetworkPatch& P = net.patches[p];
    auto length = [&](int s) { return polyline_length(net.edges[P.edges[s]].points); };
    const double span_u = (length(0) + length(2)) / (2.0 * std::max(f.nu, 1));
    const double span_v = (length(1) + length(3)) / (2.0 * std::max(f.nv, 1));
    const int d = saturated[0] != saturated[1] ? (saturated[0] ? 0 : 1) : (span_u >= span_v ? 0 : 1);
    std::ostringstream why;
    why << "accuracy: " << deviation << " > tolerance " << tol << " at " << f.nu << " x " << f.nv << " spans ("
        << (rounds_out ? "the refinement ran out of rounds" : "max_spans " + std::to_string(options.max_spans))
        << ")";
    out.push_back({{p, d, std::clamp(f.worst_uv[d], 0.25, 0.75)}, deviation, why.str()});
  }
  std::stable_sort(out.begin(), out.end(), [](const SplitChoice& a, const SplitChoice& b) {
    return a.deviation > b.deviation;
  });
  return out;
}

// The splits of one round, applied to a copy of the network.
struct SplitRound {
  std::shared_ptr<PatchNetwork> net;
  std::vector<Index> layout;         // per patch, the input network's patch
  std::vector<SplitChoice> choices;  // the cuts made, one per split
  std::vector<PatchSplit> splits;
  std::vector<bool> touched;         // per patch: in a split strip (a piece of it)
  std::vector<Index> base;           // per patch, the patch of the round's base network it is (a piece of)
};

// One split per strip: a patch a split crossed is fitted again before it is
// judged again.
SplitRound apply_splits(const PatchNetwork& base, const std::vector<Index>& layout,
                        const std::vector<SplitChoice>& choices, int round, Index budget) {
  SplitRound r{std::make_shared<PatchNetwork>(base), layout, {}, {}, std::vector<bool>(base.patches.size(), false),
               std::vector<Index>(base.patches.size())};
  std::iota(r.base.begin(), r.base.end(), 0);
  for (const SplitChoice& c : choices) {
    if (r.touched[c.cut.patch] || Index(r.splits.size()) >= budget) continue;
    const StripSplit s = split_strip(*r.net, c.cut);
    if (!s.done) continue;
    r.touched.resize(r.net->patches.size(), true);
    for (Index q : s.patches) {  // new_patches, in order
      r.touched[q] = true;
      r.layout.push_back(r.layout[q]);
      r.base.push_back(r.base[q]);
    }
    PatchSplit p;
    p.patch = c.cut.patch, p.layout_patch = r.layout[c.cut.patch];
    p.direction = c.cut.direction, p.at = c.cut.at;
    p.deviation_before = c.deviation, p.reason = c.reason;
    p.strip = s.patches, p.new_patches = s.new_patches, p.closed_strip = s.closed, p.round = round;
    r.choices.push_back(c);
    r.splits.push_back(std::move(p));
  }
  return r;
}

// How far a patch itself lies from the source: its own samples both ways
// at the fit, its surface against the source; not the source nearest to it,
// which a hole or a neighbour elsewhere may decide.
double patch_own_miss(const FitReport& r, Index p) {
  return std::max(r.per_patch[p].fit_max_deviation, r.deviation.per_patch[p].max_patch_to_source);
}

// Whether a split helped: the patch it was made for came closer to the
// source (the larger of its two pieces against it before), and no other
// patch of its strip came to lie further from it than both the tolerance
// and itself before. Each patch by its own distance (patch_own_miss): a
// hole next to it is no business of the split. (And not the strip's
// largest: another patch of the strip, over a crease, may hold it whatever
// the split does.)
// `base`: per patch after, the patch before it is (a piece of): a strip may
// run through pieces of another split of the round.
bool strip_helped(const FitReport& before, const FitReport& after, const std::vector<Index>& base,
                  const PatchSplit& s) {
  for (size_t k = 0; k < s.strip.size(); ++k) {
    const Index q = s.strip[k], n = s.new_patches[k], b = base[q];
    const double is = std::max(patch_own_miss(after, q), patch_own_miss(after, n)), was = patch_own_miss(before, b);
    if (q == s.patch ? is >= was : is > std::max(was, before.tolerance)) return false;
  }
  return true;
}

// The network's largest patch_own_miss.
double network_own_miss(const FitReport& r) {
  double worst = 0;
  for (Index p = 0; p < Index(r.per_patch.size()); ++p) worst = std::max(worst, patch_own_miss(r, p));
  return worst;
}

// A round is kept when its refit meets the tolerance, or every split of it
// helped without raising the network's largest (own) deviation or folding
// more patches.
bool round_helped(const FitReport& before, const FitReport& after, const SplitRound& r) {
  if (after.tolerance_met) return true;
  for (const PatchSplit& s : r.splits)
    if (!strip_helped(before, after, r.base, s)) return false;
  return network_own_miss(after) <= network_own_miss(before) && after.folded_patches <= before.folded_patches;
}

// Step 7: split and refit while patches miss the tolerance at their most
// spans. The splits of a round that did not help (an error along a seam,
// which every piece keeps) are undone and the rest refitted; a round that does not help is undone whole and the splitting
// stops: a miss no split mends costs a refit or two, never a worse fit.
// `layout`: per patch of the fitted network, the input network's patch.
// `other_fits_ms`: the time of the fits not kept, added to.
void split_and_refit(const Surface& surface, const PatchNetwork& network, const FitOptions& options,
                     FitResult& result, std::vector<Index>& layout, SampleMemo& memo, double& other_fits_ms) {
  std::shared_ptr<PatchNetwork> net;  // the split network, null until a round is kept
  std::vector<PatchSplit> kept, rejected;
  for (int round = 1; round <= options.split_rounds && Index(kept.size()) < options.max_splits; ++round) {
    const PatchNetwork& base = net ? *net : network;
    const Index budget = options.max_splits - Index(kept.size());
    SplitRound trial = apply_splits(base, layout, split_choices(base, result.report, options), round, budget);
    if (trial.splits.empty()) break;
    FitResult refit = fit_network(surface, *trial.net, options, memo, true);
    std::vector<SplitChoice> good;
    for (size_t k = 0; k < trial.splits.size(); ++k) {
      if (strip_helped(result.report, refit.report, trial.base, trial.splits[k])) good.push_back(trial.choices[k]);
      else rejected.push_back(trial.splits[k]);
    }
    if (!good.empty() && good.size() < trial.splits.size()) {
      other_fits_ms += 1e3 * refit.report.time_s;
      trial = apply_splits(base, layout, good, round, budget);
      refit = fit_network(surface, *trial.net, options, memo, true);
    }
    if (good.empty() || !round_helped(result.report, refit.report, trial)) {
      other_fits_ms += 1e3 * refit.report.time_s;
      if (!good.empty()) rejected.insert(rejected.end(), trial.splits.begin(), trial.splits.end());
      break;
    }
    complete_deviation(surface, options, refit);
    other_fits_ms += 1e3 * result.report.time_s;
    result = std::move(refit);
    net = std::move(trial.net);
    layout = std::move(trial.layout);
    kept.insert(kept.end(), trial.splits.begin(), trial.splits.end());
    if (result.report.tolerance_met) break;
  }
  result.report.splits = std::move(kept);
  result.report.rejected_splits = std::move(rejected);
  if (net) result.network = net;
}

// Step 6: the patches that miss at their most spans (mendable_miss) and
// whose harmonic map squashes a region enough to be the cause, mapped with
// even stretch, and the network fitted again; a patch whose own distance did
// not fall goes back to its harmonic map (one more fit). The network with
// the even maps that helped, or null when none was kept.
// Enough to be the cause: a bicubic's error falls with the fourth power of
// its knot spacing on the part, so an even map that lowers the largest
// stretch by g (even_map_gain) can take a miss of at most g^4 times the
// tolerance within it. A patch it cannot mend is not worth the trial, which
// costs the whole network a refit (the corpus: of the patches it gates out,
// gain 1.0 to 1.05 on misses of 1.1 to 2.9 times the tolerance, none came
// closer).
std::shared_ptr<PatchNetwork> even_maps_and_refit(const Surface& surface, const PatchNetwork& network,
                                                  const FitOptions& options, FitResult& result, SampleMemo& memo,
                                                  double& other_fits_ms) {
  std::vector<Index> tried;
  for (Index p = 0; p < Index(network.patches.size()); ++p) {
    const PatchFitFigures& f = result.report.per_patch[p];
    if (network.patches[p].even_stretch || !mendable_miss(f, result.report, options)) continue;
    if (std::pow(even_map_gain(network.patches[p]), 4) >= patch_miss(f) / result.report.tolerance)
      tried.push_back(p);
  }
  if (tried.empty()) return nullptr;
  auto mapped = [&](const std::vector<Index>& even) {
    auto net = std::make_shared<PatchNetwork>(network);
    for (Index p : even) net->patches[p].even_stretch = true;
    return net;
  };
  std::shared_ptr<PatchNetwork> net = mapped(tried);
  FitResult refit = fit_network(surface, *net, options, memo, true);
  std::vector<Index> helped;
  for (Index p : tried)
    if (patch_own_miss(refit.report, p) < patch_own_miss(result.report, p)) helped.push_back(p);
  if (!helped.empty() && helped.size() < tried.size()) {
    other_fits_ms += 1e3 * refit.report.time_s;
    net = mapped(helped);
    refit = fit_network(surface, *net, options, memo, true);
  }
  const FitReport &before = result.report, &after = refit.report;
  const bool kept = !helped.empty() && (after.tolerance_met || (network_own_miss(after) <= network_own_miss(before) &&
                                                                after.folded_patches <= before.folded_patches));
  if (kept) complete_deviation(surface, options, refit);
  other_fits_ms += 1e3 * (kept ? before.time_s : after.time_s);
  if (!kept) return nullptr;
  result = std::move(refit);
  return net;
}

}  // namespace

FitResult fit_patch_network(const Surface& surface, const PatchNetwork& network, const FitOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  SampleMemo memo;
  FitResult result = fit_network(surface, network, options, memo);
  std::vector<Index> layout(network.patches.size());
  std::iota(layout.begin(), layout.end(), 0);
  double other_fits_ms = 0;
  if (options.even_maps && !result.report.tolerance_met)
    result.network = even_maps_and_refit(surface, network, options, result, memo, other_fits_ms);
  if (options.split_patches && !result.report.tolerance_met) {
    const std::shared_ptr<const PatchNetwork> even = result.network;
    split_and_refit(surface, even ? *even : network, options, result, layout, memo, other_fits_ms);
  }
  FitReport& report = result.report;
  if (other_fits_ms > 0) report.timings.emplace_back("other_fits", other_fits_ms);
  const PatchNetwork& fitted = result.network ? *result.network : network;
  for (size_t p = 0; p < report.per_patch.size(); ++p) {
    report.per_patch[p].layout_patch = layout[p];
    report.per_patch[p].even_stretch = fitted.patches[p].even_stretch;
  }

  if (options.build_shell) {
    if (options.progress) options.progress->stage("sewing the shell", 0.93, 1.0);
    Stopwatch watch(report.timings);
    const double diag = network.bbox_diagonal > 0 ? network.bbox_diagonal : 1.0;
    ShellFigures fig;
    result.shell = sew_patch_shell(result.surfaces, 1e-6 * diag, &fig);
    report.faces = fig.faces, report.shells = fig.shells, report.free_edges = fig.free_edges;
    report.valid_shell = fig.valid, report.closed = fig.closed, report.solids = fig.solids;
    report.volume = fig.volume, report.shell_tolerance = fig.max_tolerance;
    watch.lap("shell");
  }
  report.time_s = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

namespace {

// The colour of a patch whose deviation is `ratio` times the tolerance, as the
// deviation picture draws it (preview.py's deviation_colour): green at 0,
// yellow at the tolerance, red at twice it and beyond, linear in between.
Vec3 deviation_colour(double ratio) {
  const Vec3 green(0.15, 0.65, 0.3), yellow(0.98, 0.85, 0.2), red(0.9, 0.15, 0.1);
  const double r = std::clamp(std::isfinite(ratio) ? ratio : 2.0, 0.0, 2.0);
  return r <= 1 ? Vec3((1 - r) * green + r * yellow) : Vec3((2 - r) * yellow + (r - 1) * red);
}

}  // namespace

Index write_step(const FitResult& result, const std::string& path) {
  std::vector<Vec3> colours;
  const double tolerance = result.report.tolerance;
  for (const PatchFitFigures& p : result.report.per_patch)
    colours.push_back(deviation_colour(tolerance > 0 ? p.max_deviation / tolerance : 0.0));
  if (result.shell) return write_step(*result.shell, path, colours);
  BoundingBox box;
  for (const BSplinePatch& p : result.surfaces)
    for (const Vec3& c : p.control) box.add(c);
  const auto shell = sew_patch_shell(result.surfaces, 1e-6 * std::max(box.diagonal(), 1e-9), nullptr);
  return write_step(*shell, path, colours);
}

}  // namespace stripweave
