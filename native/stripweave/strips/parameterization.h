// The global parameterization S of a design (paper §6.1), from which strips
// are extracted.
//
// parameterize(surface, field, loops) -> Parameterization
//   Input : the surface; its cross field (cross_field.h); the design's loops,
//           each as its embedded path and that path's per-triangle segments.
//   Method: (1) cut the surface to a topological disk through every
//           singularity: the complement of a dual spanning tree, pruned of
//           dangling branches that end at regular vertices; (2) comb the
//           field over the tree so that inside the disk it is one vector
//           field (per-triangle quarter turn `comb`), which fixes the
//           rotation r_e (multiple of 90 degrees) of the transition across
//           each cut edge; (3) one sparse least-squares solve for per-corner
//           coordinates (u, v): the gradients of u and v match the combed
//           field and its 90-degree turn (isometry plus alignment), the two
//           copies of every cut vertex are tied by the edge's transition
//           (rotation r_e, free translation per cut branch, no integer
//           rounding), and every loop is an isocurve: in each triangle a loop
//           crosses, the coordinate across the loop (v where the loop runs
//           along u, u otherwise) takes one value at both segment ends;
//           across cuts the transitions carry that value on. One point is
//           pinned (gauge). Hard constraints (not penalties): a loop's
//           points share one coordinate up to rounding (1e-9).
//   Output:
//     uv[t][i]        coordinates of corner i of triangle t (normalized units)
//     comb[t]         quarter turns applied to field.theta[t] to comb it
//     transition[e]   for an interior edge e=(t0,t1): rotation r (quarter
//                     turns, counter-clockwise) and translation tr such that
//                     a point's coordinates in t1's chart = R^r * (its
//                     coordinates in t0's chart) + tr. r = 0, tr = 0 off the
//                     cut.
//     on_cut[e]       1 if e is a cut edge
//     loop_axis[l][k] for loop l and its k-th segment, the coordinate (0 = u,
//                     1 = v) constant along it in that triangle's chart
//     loop_value[l][k] that constant value in that chart
//     flipped[t]      1 if corner coordinates are clockwise (a fold-over)
//     fold_overs      the count of flipped triangles
//     solve_ms        assembly and solve time (all of parameterize: cut,
//                     assembly, ordering, factorization, solve, output)
//   and beyond the paper, for inspection and tests:
//     cut_ends        the vertices the cut had to reach (singularities and
//                     vertices around which the field's matchings do not
//                     close up), see cut_graph.h
//     loop_points_uv[l][k]  the coordinates of the k-th segment's two end
//                     points in its triangle's chart
//     constraint_residual   the largest violation of a hard constraint
//     timings         per step, milliseconds
// Throws InputError if the constraints contradict each other (for example
// two loops asked to be isocurves of the same coordinate while crossing or
// touching: found combinatorially before the solve, since the constraints
// are homogeneous and such a design collapses S rather than leaving a
// residual) or are violated by more than 1e-9 after the solve.
// Cost: one sparse LDL^T factorization of 2 x (vertices + cut vertices)
// unknowns plus one row per constraint dominates, in the surface's nested
// dissection order (vertex_elimination_order, computed once per surface);
// at 30K triangles on one core about 100 ms of some 140 ms in all (shared
// models with 8 strips and 60 to 130 singularities).
#pragma once

#include "stripweave/strips/cross_field.h"

namespace stripweave {

struct LoopPath {
  SurfacePath path;
  bool closed = true;
  std::vector<PathSegment> segments;
};

struct Transition {
  int r = 0;
  Vec2 tr = Vec2::Zero();
  Vec2 apply(const Vec2& p) const;  // R^r p + tr
};

struct Parameterization {
  std::vector<std::array<Vec2, 3>> uv;
  std::vector<std::int8_t> comb;
  std::vector<Transition> transition;
  std::vector<std::uint8_t> on_cut;
  std::vector<std::vector<int>> loop_axis;
  std::vector<std::vector<double>> loop_value;
  std::vector<std::uint8_t> flipped;
  Index fold_overs = 0;
  double solve_ms = 0;

  std::vector<Index> cut_ends;
  std::vector<std::vector<std::array<Vec2, 2>>> loop_points_uv;
  double constraint_residual = 0;
  StageTimings timings;
};

// The elimination order the factorization follows: the surface's vertices
// in nested dissection order (sparse/nested_dissection.h). It depends on the
// mesh alone, so a caller that solves S for many designs on one surface
// (DesignState) computes it once and passes it in; left empty, parameterize
// computes it.
std::vector<Index> vertex_elimination_order(const Surface& surface);

Parameterization parameterize(const Surface& surface, const CrossField& field, const std::vector<LoopPath>& loops,
                              const std::vector<Index>& vertex_order = {});

// Two loop segments (loop, index into its segments) of different passes that
// meet, in one triangle or at a mesh vertex, while both are to be isocurves
// of the same coordinate of the field's chart, and where.
struct LoopMeeting {
  Index loop_a = kInvalid, k_a = kInvalid, loop_b = kInvalid, k_b = kInvalid;
  Vec3 where = Vec3::Zero();  // normalized units
};

// Every such meeting: the combinatorial test by which parameterize() refuses
// a design (it names the first), without the solve. Empty when every loop
// crosses every other, and itself, transversally under this field.
std::vector<LoopMeeting> contradicting_meetings(const Surface& surface, const CrossField& field,
                                                const std::vector<LoopPath>& loops);

}  // namespace stripweave
