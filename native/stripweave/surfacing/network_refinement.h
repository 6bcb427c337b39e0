// network_refinement: steps 3 and 4 of fit_patch_network.h, the fit of the
// edge curves and patches with adaptive spans and the seam condition.
//
// Input   the PatchNetwork and its NetworkTopology, the symmetry pairings
//         (a strip and its images share their span count), each edge's and
//         patch's samples (network_samples.h), per network vertex the normal
//         the edge curves leave in (zero: free), FitOptions, and
//         result.report.tolerance.
// Output  result.edge_curves and result.surfaces; in result.report the
//         refinement's own measure per patch (fit_max_deviation, spans,
//         worst sample), rounds, uncoupled_patches and the count of smooth
//         seams, sharp seams and boundary edges. Returns per network edge the
//         deviation of its curve from its samples.
// Method  Opposite sides of a quad share a knot vector, so a span count
//         belongs to a strip (the classes of edges joined by "opposite in a
//         patch": the layout's dual strips). Each round fits every dirty
//         edge curve with its strip's spans, then every patch with its
//         boundary rows fixed to the edge curves (patch_fit.h), measures the
//         orthogonal deviation at the samples (measure_patch_fits), and
//         raises the spans of the strips through anything above tolerance by
//         the cubic convergence estimate n' = n (err/tol)^(1/4), until all
//         meet it or reach max_spans. Then the smooth seams are coupled
//         (seam_mode 1: one coupled C1 fit; 0: tangent-plane targets); if the
//         coupling pushed a patch over tolerance, the spans go up again and
//         the fit restarts from the uncoupled patches (up to three times).
//         Tolerance comes before tangent continuity: a coupled patch that
//         misses where its uncoupled fit did better is uncoupled, and the
//         uncoupled network is kept whole when it meets at smaller seam
//         angles.
#pragma once

#include "stripweave/core/progress.h"
#include "stripweave/surfacing/edge_curves.h"
#include "stripweave/surfacing/fit_patch_network.h"
#include "stripweave/surfacing/network_topology.h"
#include "stripweave/surfacing/patch_fit.h"
#include "stripweave/surfacing/symmetric_fit.h"

#include <vector>

namespace stripweave {

constexpr int kMaxRefinementRounds = 40;  // refinement rounds of one fit

// The angle between two patch normals in degrees, 0 where either is zero (a
// degenerate point of a patch has no normal to jump): the seam measure.
double normal_jump_deg(const Vec3& a, const Vec3& b);

// The refinement's own measure of patches `which`: the orthogonal distance
// of each of its samples from the fitted network (its own patch, and where
// the foot point lands on its border, the nearest of the patches sharing a
// vertex with it: a patch-mesh sample by a zig-zag border may lie on the
// neighbour's side of the smooth edge curve). Side by side; `progress`
// (optional) may cancel.
void measure_patch_fits(const std::vector<BSplinePatch>& surfaces, const std::vector<Index>& which,
                        const NetworkTopology& topology, const std::vector<PatchSamples>& samples, double tolerance,
                        std::vector<PatchFitFigures>& figures, Progress* progress = nullptr);

std::vector<double> refine_network_fit(const PatchNetwork& network, const NetworkTopology& topology,
                                       const std::vector<NetworkPairing>& pairings,
                                       const std::vector<EdgeSamples>& edge_samples,
                                       std::vector<PatchSamples>& samples, const std::vector<Vec3>& vertex_normal,
                                       const FitOptions& options, FitResult& result);

}  // namespace stripweave
