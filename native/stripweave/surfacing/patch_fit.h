// Patch fit: least-squares bicubic B-spline surfaces over the unit square
// with their boundary rows fixed to the shared edge curves, optionally
// coupled across smooth seams for tangent continuity.
//
// Input   per patch: a BSplinePatch whose span counts are set and whose
//         boundary control rows already hold the edge curves' control
//         points; PatchSamples (source points at their square map's (u, v));
//         seams between patches; the thin-plate weight lambda and the seam
//         weight.
// Output  the inner control points (depth >= 1 from every side) of the
//         patches being solved; boundary rows untouched, so every side stays
//         exactly its edge curve (G0 by construction).
// Method  Minimize per patch
//           (1/K) sum_k |S(u_k, v_k) - p_k|^2
//             + lambda * E_tp,  E_tp = (1/(nu nv)) sum ( nu^4 |D_uu P|^2
//                                      + 2 nu^2 nv^2 |D_uv P|^2 + nv^4 |D_vv P|^2 ),
//         E_tp the thin-plate energy int S_uu^2 + 2 S_uv^2 + S_vv^2 in
//         control-point differences (scaled so lambda means the same at
//         every refinement), plus, per smooth seam between patches A and B
//         with shared boundary row Q_k, the C1 condition on the first inner
//         rows
//           (A_k - Q_k) + alpha (B_k - Q_k) = 0,   k = 1 .. n + 1,
//         as a quadratic penalty of weight w (relative to the mean diagonal
//         of the data term). With a common knot vector along the seam this
//         makes the cross-boundary derivatives antiparallel with the
//         constant ratio alpha at every point: G1. alpha is the ratio of
//         the two patches' cross-boundary speeds (from an uncoupled fit), so
//         the condition asks nothing of the fit that a smooth source does not
//         already have. At an irregular vertex the edge curves' tangents are
//         not collinear and G1 cannot hold at the corner itself; the
//         penalty then only spreads the compromise over the first spans.
//         x, y and z share one sparse SPD matrix (banded per patch: a
//         control couples to the 7 x 7 around it): one Eigen SimplicialLDLT.
#pragma once

#include "stripweave/surfacing/bspline.h"

namespace stripweave {

struct PatchSamples {
  std::vector<Vec2> uv;
  std::vector<Vec3> points;
};

// A smooth seam: patch a's side sa and patch b's side sb are the same edge;
// `b_reversed` when b runs that side in the opposite direction to a (the
// usual case for two consistently oriented patches).
struct Seam {
  Index a = kInvalid, b = kInvalid;
  int side_a = 0, side_b = 0;
  bool b_reversed = true;
  double alpha = 1;  // |A_k - Q_k| / |B_k - Q_k|, estimated by seam_speed_ratio
};

// A wanted position of one inner control (penalty |P(i, j) - target|^2,
// weight relative to the patch's mean data diagonal): the tangent-plane
// seam condition of fit_patch_network.
struct ControlTarget {
  Index patch = kInvalid;
  int i = 0, j = 0;
  Vec3 target = Vec3::Zero();
};

// Solve the inner controls of patches `which` (all of `patches` if empty);
// seams between two solved patches couple them with weight `seam_weight`;
// targets of solved patches pull with weight `target_weight`.
void fit_patch_interiors(std::vector<BSplinePatch>& patches, const std::vector<PatchSamples>& samples,
                         const std::vector<Index>& which, const std::vector<Seam>& seams, double smoothing,
                         double seam_weight, const std::vector<ControlTarget>& targets = {},
                         double target_weight = 0);

// The ratio of the cross-boundary control offsets of a over b along a seam.
double seam_speed_ratio(const std::vector<BSplinePatch>& patches, const Seam& seam);

// Orthogonal distance from p to the patch, by Gauss-Newton from `uv`
// (clamped to the square); the foot point's (u, v) in *foot if given.
double distance_to_patch(const BSplinePatch& patch, const Vec3& p, Vec2 uv, Vec2* foot = nullptr);

}  // namespace stripweave
