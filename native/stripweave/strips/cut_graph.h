// The cut graph of a cross field and the field combed over it (paper §6.1,
// the first two steps of cross-field-guided parameterization after Kälberer
// et al. 2007 and Bommes et al. 2009).
//
// cut_to_disk(surface, field) -> CutGraph
//   Input : the surface and its cross field (cross_field.h).
//   Method:
//     Matching. Across every interior edge e = (t0, t1) the field of t0 is
//       carried into t1's plane by the hinge map about e (the discrete
//       Levi-Civita connection) and compared with t1's cross: matching[e] is
//       the quarter turn r with d1 ~ R^r (transported d0). It is rounded here
//       from the field's 3D directions, so that combing, cut and holonomy use
//       one and the same matching whatever angle conventions produced the
//       field.
//     Holonomy. Around an interior vertex the matchings add up (mod 4) to the
//       quarter turn the cross suffers when carried once around; a vertex
//       with a non-zero sum cannot lie inside a chart, so the cut must reach
//       it. Together with the field's own singularities (non-zero index) these
//       are the cut's ends.
//     Dual spanning tree. A breadth-first tree over the triangles (crossing
//       interior edges), one per connected component; combing along it
//       (comb[t1] = comb[t0] - matching) leaves every tree edge with combed
//       matching 0.
//     Cut. The interior edges not crossed by the tree, pruned of dangling
//       branches: an edge is dropped while one of its vertices is an interior
//       vertex of zero holonomy that is not a singularity and has no other cut
//       edge. What remains cuts every component into a topological disk whose
//       charts fit together (on a closed surface of genus g: 2g cycles plus
//       branches to the singularities; where there is an open boundary the
//       cut may end on it). Every edge off the cut then has combed matching 0.
//     Wedges. The corners of the triangles around a vertex that stay
//       connected through edges off the cut: one copy of the vertex per side
//       of the cut (one wedge for a vertex off the cut).
//   Output (indexed by element):
//     matching[e]        r in 0..3, from edge_triangles[e][0] to [1]; 0 on
//                        boundary edges
//     comb[t]            quarter turns applied to the field in t
//     combed_matching[e] matching[e] + comb[t1] - comb[t0] (mod 4): the
//                        combed field of t1 ~ R^r (transported combed field
//                        of t0); 0 off the cut
//     on_cut[e]          1 for a cut edge
//     cut_ends           the vertices the cut was required to reach
//                        (singularities and vertices of non-zero holonomy)
//     wedge[3t+i]        the wedge of corner i of triangle t
//     wedge_vertex[w]    the mesh vertex of wedge w
//     component[t]       the connected component of triangle t
//     tree_root[c]       the root triangle of component c's dual tree
//   Cost: linear in the mesh size (a few ms at 30K triangles).
#pragma once

#include "stripweave/strips/cross_field.h"

namespace stripweave {

struct CutGraph {
  std::vector<std::int8_t> matching;
  std::vector<std::int8_t> comb;
  std::vector<std::int8_t> combed_matching;
  std::vector<std::uint8_t> on_cut;
  std::vector<Index> cut_ends;
  std::vector<Index> wedge;
  std::vector<Index> wedge_vertex;
  std::vector<Index> component;
  std::vector<Index> tree_root;

  Index num_wedges() const { return static_cast<Index>(wedge_vertex.size()); }
  Index num_components() const { return static_cast<Index>(tree_root.size()); }
  Index wedge_of(Index t, int corner) const { return wedge[3 * t + corner]; }
};

CutGraph cut_to_disk(const Surface& surface, const CrossField& field);

// The unit normal of triangle t.
Vec3 unit_normal(const TriangleMesh& mesh, Index t);

// A tangent vector of a triangle with unit normal n turned by r quarter turns
// counter-clockwise about n.
Vec3 quarter_turn(const Vec3& x, const Vec3& n, int r);

// The field's direction in triangle t, combed: field.direction[t] projected
// onto t's plane, normalized and turned by comb[t] quarter turns.
Vec3 combed_direction(const Surface& surface, const CrossField& field, const CutGraph& cut, Index t);

}  // namespace stripweave
