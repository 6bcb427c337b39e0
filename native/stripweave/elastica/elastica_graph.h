// ElasticaGraph: the graph g over the surface and its line graph g' (paper §5.3).
//
// g : nodes are the mesh vertices; every pair of vertices at graph distance
//     <= k is joined by two directed g-edges, realized as surface geodesics.
//     Length and end tangents are measured on the surface, with local
//     geodesic polar coordinates (a discrete exponential map over each
//     vertex's k-ring), not from the straight chord. Geodesics do not pass
//     through sharp-feature or boundary vertices: they may end on one, so a
//     curve crosses a feature exactly at a g-vertex, where §5.6 applies.
//     Hence "graph distance" counts paths whose inner vertices are off
//     features and boundaries, and a pair is left out where its geodesic
//     could only touch such a vertex, or where the two ends' maps disagree
//     on its length by more than 5% (together about 1% of pairs on CAD
//     parts with many creases, none on smooth closed surfaces).
// g': nodes are the directed g-edges ("nodes" below); a g'-edge ("arc")
//     joins (u->v) to (v->w) when the turning angle gamma at v, measured in
//     v's tangent plane, is at most max_turn. Its weight is eq. (2):
//        w = |e'| + alpha q(e') + beta gamma^2 / min(|e0|, |e1|)
//     |e'| = gamma min(|e0|,|e1|) / (2 tan(gamma/2)) + ||e0| - |e1|| / 2
//     q(e') = (q_n0(e0) + q_n1(e1)) / 2 * |e'|
//     q_n(e) = anisotropy * dev(t): (|k_min| - |k_max|)^2 (1/max(|<t,d_min>|,
//     |<t,d_max>|) - 1) at regular points, feature_weight (1/|<t,c>| - 1) on
//     features and aligned boundaries (c: across the curve), evaluated at
//     both ends of the g-edge and averaged (the trapezoid rule at its
//     midpoint).
//
// Storage is compact: CSR arrays, 32-bit ids, float weights.
//
// Conventions
//   node ids: the outgoing g-edges of vertex v are the nodes
//             [node_offsets[v], node_offsets[v+1]), sorted by polar angle.
//   angle[n]: the departure direction of node n=(v->w) at v, as a polar angle
//             in v's tangent frame (frame[v], normal[v] x frame[v]); angles are
//             scaled so that a full turn around v is 2 pi, hence a straight
//             curve through v leaves at its arrival angle plus pi. (Around an
//             open-boundary vertex the half fan keeps its true angles.) The
//             angles are intrinsic (local geodesic polar coordinates, see
//             local_geodesic_map.h): at a crease both sides are unfolded into
//             the plane of normal[v], the mean of the two sides' normals, so a
//             curve crossing the crease orthogonally has turn 0 there.
//   turn((u->v),(v->w)) = |wrap_pi(angle[v->w] - angle[v->u] - pi)|.
//   length:   symmetric, |v->w| == |w->v| (the mean of the two maps' values),
//             and alignment[v->w] == alignment[w->v] (q is pi-periodic), so
//             every arc weight equals that of its reversed arc.
//   frame[v]: on a feature vertex it runs along the feature (its first
//             feature edge), on a boundary vertex along the boundary.
//   q_n on features (and aligned boundaries): c is perpendicular, in the
//             unfolded tangent plane, to the curve's tangent (the bisector of
//             its two edges); where the curve ends or several meet (a corner)
//             the largest deviation over the incident curve edges is used.
//             1/|<t,c>| is clamped to 1e4, so a node along a feature is
//             effectively, not literally, forbidden.
#pragma once

#include "stripweave/core/progress.h"
#include "stripweave/elastica/elastica_params.h"
#include "stripweave/surface/surface.h"

#include <cstdint>

namespace stripweave {

struct ElasticaGraph {
  ElasticaParams params;

  // g, per vertex
  std::vector<Index> node_offsets;  // size |V|+1
  std::vector<Vec3> frame;          // unit tangent e1 of each vertex's polar angles
  std::vector<Vec3> normal;         // unit normal of that tangent plane (e2 = normal x frame)

  // g, per directed g-edge = g' node
  std::vector<Index> tail, head;  // v and w of (v->w)
  std::vector<Index> reverse;     // the node (w->v)
  std::vector<float> length;      // geodesic length |e|
  std::vector<float> angle;       // departure polar angle at the tail, [0, 2 pi)
  std::vector<float> alignment;   // q_n(e) at the edge midpoint (alpha not applied)

  // g', CSR over nodes
  std::vector<Index> arc_offsets;  // size nodes+1
  std::vector<Index> arc_head;     // successor node of each arc
  std::vector<float> arc_weight;   // w(e') of eq. (2)

  Index num_nodes() const { return static_cast<Index>(head.size()); }
  Index num_arcs() const { return static_cast<Index>(arc_head.size()); }
  std::size_t memory_bytes() const;

  // Turning angle gamma (radians) at the shared vertex between consecutive nodes.
  double turn(Index from, Index to) const;
  // The 3D unit departure tangent of a node at its tail.
  Vec3 tangent(const Surface& surface, Index node) const;
  // The terms of eq. (2) for the arc from -> to (from.head == to.tail).
  struct ArcTerms {
    double length, alignment, curvature;  // |e'|, alpha q(e'), beta kappa^2(e')
  };
  ArcTerms arc_terms(Index from, Index to) const;
};

// Build g and g' for a surface. Cancellable through `progress` (reports
// advance(0..1) within the caller's current stage, throws Cancelled). Uses up
// to two threads for the per-vertex geodesic maps; the result does not depend
// on the thread count. Throws InputError for parameters out of range (k not in
// 1..16, max_turn_deg not in (0, 180], negative weights).
ElasticaGraph build_elastica_graph(const Surface& surface, const ElasticaParams& params,
                                   Progress* progress = nullptr);

}  // namespace stripweave
