#include "stripweave/surfacing/network_refinement.h"

#include "stripweave/core/parallel.h"
#include "stripweave/core/union_find.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace stripweave {

namespace {


bool on_border(const Vec2& uv) {
  return uv.x() <= 1e-9 || uv.x() >= 1 - 1e-9 || uv.y() <= 1e-9 || uv.y() >= 1 - 1e-9;
}

// Per patch, its points at the nodes of a 5 x 5 grid over the square: the
// nearest node starts the search on a neighbour (distance_to_network). Made
// once per measure: evaluated afresh for every border sample and neighbour,
// these 25 evaluations were most of the measure.
constexpr int kStartGrid = 5;
using StartGrid = std::array<Vec3, kStartGrid * kStartGrid>;

StartGrid start_grid(const BSplinePatch& patch) {
  StartGrid g;
  for (int i = 0; i < kStartGrid; ++i)
    for (int j = 0; j < kStartGrid; ++j)
      g[i * kStartGrid + j] = patch.value(i / double(kStartGrid - 1), j / double(kStartGrid - 1));
  return g;
}

// The (u, v) of the grid node nearest to x (the first of equals).
Vec2 nearest_start(const StartGrid& g, const Vec3& x) {
  Vec2 start(0.5, 0.5);
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kStartGrid; ++i)
    for (int j = 0; j < kStartGrid; ++j) {
      const double e = (g[i * kStartGrid + j] - x).squaredNorm();
      if (e < best) best = e, start = Vec2(i / double(kStartGrid - 1), j / double(kStartGrid - 1));
    }
  return start;
}

// Orthogonal deviation of one sample from the fitted network: the own
// patch, and where the foot point lands on its border, the nearest of its
// neighbours (each from the nearest node of its start grid). `enough`: a
// sample this close needs no search among the neighbours.
double distance_to_network(const std::vector<BSplinePatch>& patches, const std::vector<StartGrid>& starts, Index p,
                           const std::vector<Index>& neighbours, const Vec3& x, const Vec2& uv, double enough) {
  Vec2 foot;
  double d = distance_to_patch(patches[p], x, uv, &foot);
  if (!on_border(foot) || d <= enough) return d;
  for (Index q : neighbours) {
    d = std::min(d, distance_to_patch(patches[q], x, nearest_start(starts[q], x), nullptr));
    if (d <= enough) break;
  }
  return d;
}

void measure_patch(const std::vector<BSplinePatch>& patches, const std::vector<StartGrid>& starts, Index p,
                   const std::vector<Index>& neighbours, const PatchSamples& s, double enough, PatchFitFigures& fig) {
  const BSplinePatch& patch = patches[p];
  double worst = 0, sum2 = 0;
  for (size_t k = 0; k < s.points.size(); ++k) {
    const double d = distance_to_network(patches, starts, p, neighbours, s.points[k], s.uv[k], enough);
    if (d > worst) worst = d, fig.worst_uv = s.uv[k];
    sum2 += d * d;
  }
  fig.fit_max_deviation = worst;
  fig.fit_rms_deviation = s.points.empty() ? 0 : std::sqrt(sum2 / s.points.size());
  fig.samples = static_cast<Index>(s.points.size());
  fig.nu = patch.nu, fig.nv = patch.nv;
}

// The smooth seams (two patches, neither sharp nor boundary), which the
// coupling joins; the report counts them, the sharp seams and the boundary
// edges.
std::vector<Seam> smooth_seams(const PatchNetwork& network, const NetworkTopology& topology, FitReport& report) {
  std::vector<Seam> seams;
  for (Index e = 0; e < Index(network.edges.size()); ++e) {
    const NetworkEdge& E = network.edges[e];
    const auto& uses = topology.uses[e];
    if (uses.size() == 1 || E.boundary) {
      ++report.boundary_edges;
      continue;
    }
    if (uses.size() != 2) continue;
    if (E.sharp) {
      ++report.sharp_seams;
      continue;
    }
    ++report.smooth_seams;
    Seam s;
    s.a = uses[0].patch, s.side_a = uses[0].side;
    s.b = uses[1].patch, s.side_b = uses[1].side;
    s.b_reversed = uses[0].reversed != uses[1].reversed;
    if (s.a == s.b) continue;  // a patch glued to itself: leave it C0
    seams.push_back(s);
  }
  return seams;
}

// Largest normal-angle jump over the middle ([seam_from, seam_to]) of the
// smooth seams.
double seam_angle(const std::vector<BSplinePatch>& surfaces, const std::vector<Seam>& seams,
                  const FitOptions& options) {
  double worst = 0;
  for (const Seam& sm : seams)
    for (int k = 0; k <= 20; ++k) {
      const double t = options.seam_from + (options.seam_to - options.seam_from) * k / 20.0;
      const Vec2 ua = side_uv(sm.side_a, t), ub = side_uv(sm.side_b, sm.b_reversed ? 1 - t : t);
      worst = std::max(worst, normal_jump_deg(surfaces[sm.a].normal(ua.x(), ua.y()), surfaces[sm.b].normal(ub.x(), ub.y())));
    }
  return worst;
}

// seam_mode 0: at each control m of a seam's shared boundary row Q, the
// mean of both patches' normals at the Greville point; each patch's first
// inner control is pulled to its projection onto the plane through Q_m
// normal to it.
std::vector<ControlTarget> tangent_plane_targets(const std::vector<BSplinePatch>& surfaces,
                                                 const std::vector<Seam>& seams) {
  std::vector<ControlTarget> targets;
  for (const Seam& sm : seams) {
    const BSplinePatch &A = surfaces[sm.a], &B = surfaces[sm.b];
    const int N = side_size(A, sm.side_a);
    if (side_size(B, sm.side_b) != N) continue;
    const int n = N - 3;  // spans along the seam
    auto knot = [&](int j) { return std::clamp(double(j - 3) / n, 0.0, 1.0); };
    for (int m = 1; m <= N - 2; ++m) {
      const int mb = sm.b_reversed ? N - 1 - m : m;
      const double t = (knot(m + 1) + knot(m + 2) + knot(m + 3)) / 3;  // Greville
      const Vec2 ua = side_uv(sm.side_a, t), ub = side_uv(sm.side_b, sm.b_reversed ? 1 - t : t);
      const Vec3 na = A.normal(ua.x(), ua.y()), nb = B.normal(ub.x(), ub.y());
      Vec3 nm = na + (na.dot(nb) >= 0 ? nb : Vec3(-nb));
      if (nm.norm() <= 1e-12) continue;
      nm.normalize();
      const auto q = side_control(A, sm.side_a, m, 0);
      const Vec3 Q = A.P(q[0], q[1]);
      const auto ca = side_control(A, sm.side_a, m, 1);
      const auto cb = side_control(B, sm.side_b, mb, 1);
      const Vec3 a = A.P(ca[0], ca[1]), b = B.P(cb[0], cb[1]);
      targets.push_back({sm.a, ca[0], ca[1], Vec3(a - (a - Q).dot(nm) * nm)});
      targets.push_back({sm.b, cb[0], cb[1], Vec3(b - (b - Q).dot(nm) * nm)});
    }
  }
  return targets;
}

// The state of one network's refinement: spans per strip, what is dirty.
class Refinement {
 public:
  Refinement(const PatchNetwork& network, const NetworkTopology& topology,
             const std::vector<NetworkPairing>& pairings, const std::vector<EdgeSamples>& edge_samples,
             std::vector<PatchSamples>& samples, const std::vector<Vec3>& vertex_normal, const FitOptions& options,
             FitResult& result)
      : network_(network), topology_(topology), edge_samples_(edge_samples), samples_(samples),
        vertex_normal_(vertex_normal), options_(options), result_(result), report_(result.report),
        tol_(result.report.tolerance), nE_(Index(network.edges.size())), nP_(Index(network.patches.size())),
        strip_of_(nE_), spans_(nE_, std::max(1, options.initial_spans)), edge_dev_(nE_, 0.0),
        edge_dirty_(nE_, true), patch_dirty_(nP_, true), fit_samples_(samples) {
    UnionFind strips(nE_);  // over network edges: the layout's strips
    for (const NetworkPatch& P : network.patches) {
      strips.unite(P.edges[0], P.edges[2]);
      strips.unite(P.edges[1], P.edges[3]);
    }
    for (const NetworkPairing& pairing : pairings)
      if (pairing.paired)
        for (Index e = 0; e < nE_; ++e) strips.unite(e, pairing.edge_image[e]);
    for (Index e = 0; e < nE_; ++e) strip_of_[e] = strips.find(e);
    result.edge_curves.assign(nE_, {});
    result.surfaces.assign(nP_, {});
    report_.per_patch.assign(nP_, {});
  }

  std::vector<double> run();

 private:
  void set_boundary(Index p);
  void correct_parameters(Index p);
  void fit_round();
  bool refine();
  void couple(const std::vector<Seam>& seams);
  void keep_tolerance_first(const std::vector<Seam>& seams, const std::vector<BSplinePatch>& uncoupled,
                            const std::vector<PatchFitFigures>& uncoupled_fig);
  void check() const {
    if (options_.progress) options_.progress->check();
  }

  const PatchNetwork& network_;
  const NetworkTopology& topology_;
  const std::vector<EdgeSamples>& edge_samples_;
  std::vector<PatchSamples>& samples_;
  const std::vector<Vec3>& vertex_normal_;
  const FitOptions& options_;
  FitResult& result_;
  FitReport& report_;
  const double tol_;
  const Index nE_, nP_;
  std::vector<Index> strip_of_;  // per edge, its strip's root edge
  std::vector<int> spans_;       // per strip root
  std::vector<double> edge_dev_;
  std::vector<bool> edge_dirty_, patch_dirty_;
  std::vector<PatchSamples> fit_samples_;  // the samples the fit takes (parameter_corrections drop border ones)
};

// Patch p's boundary rows: its edge curves' control points.
void Refinement::set_boundary(Index p) {
  const NetworkPatch& P = network_.patches[p];
  BSplinePatch& B = result_.surfaces[p];
  B.nu = spans_[strip_of_[P.edges[0]]];
  B.nv = spans_[strip_of_[P.edges[1]]];
  B.control.assign(size_t(B.rows()) * B.cols(), Vec3::Zero());
  for (int s = 0; s < 4; ++s) {
    const BSplineCurve3& c = result_.edge_curves[P.edges[s]];
    const int N = side_size(B, s);
    for (int k = 0; k < N; ++k) {
      const auto ij = side_control(B, s, k, 0);
      B.P(ij[0], ij[1]) = c.control[P.reversed[s] ? N - 1 - k : k];
    }
  }
}

// Parameter correction: each sample's (u, v) becomes its foot point on the
// current fit, and samples whose foot point lies on the patch border
// (beyond the smooth edge curve, the neighbour's side of a zig-zag mesh edge
// path) leave the fit. The harmonic map puts the patch mesh's zig-zag
// boundary on the square's sides, so near the border it is off by up to
// half a mesh edge across the seam: fitted as they are, these samples bend
// the patch to reconcile parameters that disagree with the edge curves.
void Refinement::correct_parameters(Index p) {
  const BSplinePatch& B = result_.surfaces[p];
  PatchSamples& S = samples_[p];
  PatchSamples& F = fit_samples_[p];
  F.uv.clear(), F.points.clear();
  for (size_t k = 0; k < S.points.size(); ++k) {
    Vec2 foot;
    distance_to_patch(B, S.points[k], S.uv[k], &foot);
    S.uv[k] = foot;
    if (!on_border(foot)) F.uv.push_back(foot), F.points.push_back(S.points[k]);
  }
}

// The dirty edge curves, then the dirty patches, then their measure.
void Refinement::fit_round() {
  for (Index e = 0; e < nE_; ++e)
    if (edge_dirty_[e]) {
      const NetworkEdge& E = network_.edges[e];
      result_.edge_curves[e] =
          fit_edge_curve(edge_samples_[e], network_.vertices[E.v0], network_.vertices[E.v1], spans_[strip_of_[e]],
                         options_.smoothing, vertex_normal_[E.v0], vertex_normal_[E.v1]);
      edge_dev_[e] = edge_curve_deviation(result_.edge_curves[e], edge_samples_[e]);
    }
  std::vector<Index> which;
  for (Index p = 0; p < nP_; ++p)
    if (patch_dirty_[p]) set_boundary(p), which.push_back(p);
  if (!which.empty()) {
    fit_patch_interiors(result_.surfaces, fit_samples_, which, {}, options_.smoothing, 0);
    for (int c = 0; c < options_.parameter_corrections; ++c) {
      for (Index p : which) correct_parameters(p);
      fit_patch_interiors(result_.surfaces, fit_samples_, which, {}, options_.smoothing, 0);
    }
  }
  measure_patch_fits(result_.surfaces, which, topology_, samples_, tol_, report_.per_patch);
  std::fill(edge_dirty_.begin(), edge_dirty_.end(), false);
  std::fill(patch_dirty_.begin(), patch_dirty_.end(), false);
}

// Raise the span count of the strips through everything above tolerance;
// false when nothing can go up.
bool Refinement::refine() {
  std::vector<int> want(nE_, 0);
  auto ask = [&](Index e, double err) {
    const Index r = strip_of_[e];
    const int n = spans_[r];
    if (n >= options_.max_spans) return;
    const double factor = std::pow(std::max(err / tol_, 1.0), 0.25) * 1.15;
    const int m = std::min(options_.max_spans, std::max(n + 1, static_cast<int>(std::ceil(n * factor))));
    want[r] = std::max(want[r], m);
  };
  for (Index e = 0; e < nE_; ++e)
    if (edge_dev_[e] > tol_ && !topology_.uses[e].empty()) ask(e, edge_dev_[e]);
  for (Index p = 0; p < nP_; ++p)
    if (report_.per_patch[p].fit_max_deviation > tol_)
      for (int s = 0; s < 2; ++s) ask(network_.patches[p].edges[s], report_.per_patch[p].fit_max_deviation);
  bool changed = false;
  for (Index r = 0; r < nE_; ++r)
    if (want[r] > spans_[r]) spans_[r] = want[r], changed = true;
  if (!changed) return false;
  for (Index e = 0; e < nE_; ++e) edge_dirty_[e] = spans_[strip_of_[e]] != result_.edge_curves[e].spans;
  for (Index p = 0; p < nP_; ++p)
    for (int s = 0; s < 4; ++s) patch_dirty_[p] = patch_dirty_[p] || edge_dirty_[network_.patches[p].edges[s]];
  return true;
}

// Step 4: the seam condition across the smooth seams, then the measure.
void Refinement::couple(const std::vector<Seam>& given) {
  if (options_.seam_mode == 1) {
    std::vector<Seam> seams = given;
    for (Seam& s : seams) s.alpha = seam_speed_ratio(result_.surfaces, s);
    fit_patch_interiors(result_.surfaces, fit_samples_, {}, seams, options_.smoothing, options_.seam_weight);
  } else {
    for (int round = 0; round < std::max(1, options_.tangent_rounds); ++round)
      fit_patch_interiors(result_.surfaces, fit_samples_, {}, {}, options_.smoothing, 0,
                          tangent_plane_targets(result_.surfaces, given), options_.seam_weight);
  }
  std::vector<Index> all(nP_);
  std::iota(all.begin(), all.end(), 0);
  measure_patch_fits(result_.surfaces, all, topology_, samples_, tol_, report_.per_patch, options_.progress);
}

// Refinement is exhausted: tolerance before tangent continuity. A patch the
// coupling pushed further over tolerance than its uncoupled fit goes back to
// that; and the seam condition is a means to tangent continuity, not an end:
// where the uncoupled fits already meet better at the smooth seams (an
// accurate fit of a smooth source is nearly G1 by itself, and the condition,
// being stronger than G1, can cost more than it gives), they are kept.
void Refinement::keep_tolerance_first(const std::vector<Seam>& seams, const std::vector<BSplinePatch>& uncoupled,
                                      const std::vector<PatchFitFigures>& uncoupled_fig) {
  for (Index p = 0; p < nP_; ++p)
    if (report_.per_patch[p].fit_max_deviation > tol_ &&
        uncoupled_fig[p].fit_max_deviation < report_.per_patch[p].fit_max_deviation) {
      result_.surfaces[p] = uncoupled[p];
      report_.per_patch[p] = uncoupled_fig[p];
      ++report_.uncoupled_patches;
    }
  if (seam_angle(uncoupled, seams, options_) < seam_angle(result_.surfaces, seams, options_)) {
    result_.surfaces = uncoupled;
    report_.per_patch = uncoupled_fig;
    report_.uncoupled_patches = nP_;
  }
}

std::vector<double> Refinement::run() {
  const std::vector<Seam> seams = smooth_seams(network_, topology_, report_);
  for (int outer = 0; outer < 3; ++outer) {
    do {
      check();
      fit_round();
      ++report_.rounds;
    } while (report_.rounds < kMaxRefinementRounds && refine());
    if (seams.empty() || options_.seam_weight <= 0) break;
    const std::vector<BSplinePatch> uncoupled = result_.surfaces;
    const std::vector<PatchFitFigures> uncoupled_fig = report_.per_patch;
    couple(seams);
    // If the coupling pushed a patch over tolerance, refine and go again,
    // from the uncoupled fits: a round refits only the patches whose spans
    // changed, and the others must not keep their coupled interiors: a
    // network half coupled, half not, meets at the largest seam angles of
    // all (the lofted part of tests/test_refit.py with two belts, at 20,000
    // triangles: 7.1 degrees over the middle of its seams and 3.9 at its
    // regular ones, where all uncoupled meet at 0.9 and all coupled at 0.2;
    // now 0.14 and 1.2).
    if (report_.rounds < kMaxRefinementRounds && outer < 2 && refine()) {
      for (Index p = 0; p < nP_; ++p)
        if (!patch_dirty_[p]) result_.surfaces[p] = uncoupled[p], report_.per_patch[p] = uncoupled_fig[p];
      continue;
    }
    keep_tolerance_first(seams, uncoupled, uncoupled_fig);
    break;
  }
  return edge_dev_;
}

}  // namespace

double normal_jump_deg(const Vec3& a, const Vec3& b) {
  if (a.isZero() || b.isZero()) return 0;
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

void measure_patch_fits(const std::vector<BSplinePatch>& surfaces, const std::vector<Index>& which,
                        const NetworkTopology& topology, const std::vector<PatchSamples>& samples, double tolerance,
                        std::vector<PatchFitFigures>& figures, Progress* progress) {
  const double enough = 1e-2 * tolerance;
  // The start grids of the patches measured and their neighbours.
  const Index nP = static_cast<Index>(surfaces.size());
  std::vector<bool> needed(nP, false);
  for (Index p : which) {
    needed[p] = true;
    for (Index q : topology.neighbours[p]) needed[q] = true;
  }
  std::vector<StartGrid> starts(nP);
  parallel_for(nP, [&](Index p) {
    if (needed[p]) starts[p] = start_grid(surfaces[p]);
  });
  parallel_for(static_cast<Index>(which.size()), [&](Index k) {
    if (progress) progress->check();
    const Index p = which[k];
    measure_patch(surfaces, starts, p, topology.neighbours[p], samples[p], enough, figures[p]);
  });
}

std::vector<double> refine_network_fit(const PatchNetwork& network, const NetworkTopology& topology,
                                       const std::vector<NetworkPairing>& pairings,
                                       const std::vector<EdgeSamples>& edge_samples,
                                       std::vector<PatchSamples>& samples, const std::vector<Vec3>& vertex_normal,
                                       const FitOptions& options, FitResult& result) {
  Refinement refinement(network, topology, pairings, edge_samples, samples, vertex_normal, options, result);
  return refinement.run();
}

}  // namespace stripweave
