// Edge curves: one cubic B-spline per network edge, shared by the (one or
// two) patches the edge bounds.
//
// Input   the edge's samples (points on the exact source, in order from v0
//         to v1), its end vertices, the span count n (shared by every edge
//         of its strip, see fit_patch_network.h) and the thin-plate weight.
// Output  a BSplineCurve3 with n uniform spans whose first and last control
//         points are exactly the end vertices (clamped: the curve
//         interpolates them), so patches meeting at a vertex meet exactly.
// Method  Chord-length parameters t_k of the samples (normalized to
//         [0, 1]); least squares of the n + 1 inner control points to the
//         samples,
//             (1/K) sum_k |C(t_k) - p_k|^2 + lambda n^3 sum_i |P_{i-1} - 2P_i + P_{i+1}|^2,
//         the second term a discrete bending energy (int |C''|^2, scaled
//         with n so lambda means the same at every refinement) that only
//         steadies spans with few samples. One small dense LDLT.
//
// sample_edge() densifies the polyline (each segment split into `density`
// parts) and projects every point onto the source, so an edge fitted on a
// coarse solver-mesh polyline still follows the exact B-rep curve.
// With smooth > 0 (smooth edges, never sharp or boundary ones) the samples
// are first filtered with a Gaussian of sigma = smooth mean polyline
// segments along the arc length (odd reflection at the ends, which keeps
// the end vertices and a straight run as they are) and then projected
// again: a layout edge is a path of mesh edges that zig-zags by up to half
// a mesh edge across its course, a wiggle that is no part of the geometry
// and that a faithful edge curve would carry into both patches.
#pragma once

#include "stripweave/surfacing/bspline.h"
#include "stripweave/surfacing/source_projection.h"

namespace stripweave {

struct EdgeSamples {
  std::vector<Vec3> points;  // from v0 to v1, on the source
  std::vector<double> t;     // normalized chord length
};

// `point_faces[k]`: the B-rep faces polyline point k may lie on (empty
// without a B-rep). Sharp edges are projected onto the B-rep edge curves.
EdgeSamples sample_edge(const std::vector<Vec3>& polyline, const std::vector<std::vector<Index>>& point_faces,
                        bool sharp, const SourceProjector& projector, int density, double smooth = 0);

// start_normal / end_normal (zero: none): the surface normal at a smooth
// vertex. The curve's end tangent (P_1 - P_0) is then held in the tangent
// plane there, so every edge curve at the vertex leaves it in one plane and
// the patch corners meeting there share their normal (G1 at the vertex:
// a corner's normal is the cross product of its two sides' end tangents).
// Only where the free fit's end tangent is within 5 degrees of the plane:
// farther out, holding it would bend the curve into a hook.
BSplineCurve3 fit_edge_curve(const EdgeSamples& samples, const Vec3& start, const Vec3& end, int spans,
                             double smoothing, const Vec3& start_normal = Vec3::Zero(),
                             const Vec3& end_normal = Vec3::Zero());

// Largest distance from the samples to the curve (foot points by Newton
// iteration from the sample's own parameter).
double edge_curve_deviation(const BSplineCurve3& curve, const EdgeSamples& samples);

}  // namespace stripweave
