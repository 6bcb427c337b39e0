// The strict checks of a quad layout (issue 16): what keeps a layout that is
// valid in the paper's sense (no red region) from being a clean quad layout a
// CAD engineer can surface.
//
// find_layout_defects(surface, arrangement, layout) -> LayoutDefects
//   Input : the surface, the loops' arrangement (its refined mesh is where the
//           layout is embedded), the QuadLayout built on it (an invalid
//           layout, with no patches, included), and per surface edge whether
//           it is a crease (creases_of, creases.h; empty: computed here).
//   Checks (normalized units inside, positions in the output in model units):
//     non_quad      a patch whose boundary does not read as four sides
//                   (PrimalPatch::quad false), or one of whose four sides
//                   collapses to a point (shorter than one mean solver edge:
//                   two of its corners are then one), or one of whose sides
//                   comes straight back along the side before it (the same
//                   edge run the other way: a slit whose tip is a vertex of
//                   valence 1). Corners may coincide
//                   where sides are closed edges of positive length: a
//                   torus's one-patch layout is a quad layout (paper §2).
//     overlapping_edges  two primal edge paths meet at a refined vertex that
//                   is not a primal vertex both end at (a shared stretch, a
//                   touch, an edge passing through another's end), or one
//                   path visits a refined vertex twice. Counted as EDGES
//                   involved; one location per touching pair (at the first
//                   refined vertex where they meet).
//     valence2      a primal vertex with two edges or one: a patch corner
//                   of about 180 degrees (two), or the tip of a dangling
//                   edge, a corner of 360 degrees (one), unless the part
//                   forces it (below; the corner of a sheet). A vertex no
//                   edge reaches is no patch's corner: the surface around it
//                   lies in no patch, which `uncovered` counts.
//     high_valence  a primal vertex with more than 6 edges where the part
//                   does not force as many. The geometric rule: every crease
//                   and every boundary curve leaving a corner of the part
//                   (a crease junction, or a boundary corner:
//                   corner_strength > 0, corner_strength.h) must be followed
//                   by its own primal edge, so a primal vertex AT such a
//                   corner (its refined vertex is that surface vertex) needs
//                   at least n edges, n the crease and boundary edges of the
//                   surface there (creases_of, creases.h). The vertex is
//                   flagged when valence > max(6, n); a vertex elsewhere
//                   when valence > 6. The same n exempts a vertex of valence
//                   2 or less when n >= 2.
//     creased       PrimalPatch::creased(): a crease runs inside the patch.
//     degenerate    a patch whose area is under kDegenerateArea (1e-4) of
//                   the surface's area, or whose inscribed radius is under
//                   kDegenerateRadius (2) mean solver edge lengths. The
//                   inscribed radius is the largest distance from a patch
//                   vertex to the patch's boundary (primal edges, the open
//                   boundary, and where it borders no patch or another one),
//                   by multi-source Dijkstra over the refined mesh's edges
//                   within the patch (an upper bound of the geodesic one).
//                   A patch narrower than that radius only because the part
//                   is (its inradius at least kForcedWidth of its crease
//                   width: the largest distance of its vertices from a
//                   crease or the open boundary, e.g. the side wall of a
//                   thin plate) is not degenerate by the radius.
//     uncovered     a triangle of the SURFACE (solver mesh; each refined
//                   triangle lies in one) some part of which lies in no
//                   patch or in two (a refined triangle listed by no patch's
//                   triangles, or by two). An invalid layout has no patches,
//                   so every surface triangle is uncovered. Located once per
//                   connected piece of uncovered triangles.
//   Output: counts per kind, the defect kinds of each patch, vertex and edge
//           (indexed like QuadLayout's), and one location per defect (per
//           pair of edges, per uncovered piece): a point on the surface in
//           model units (a patch's vertex nearest its centroid, the primal
//           vertex, the touching point, an uncovered piece's triangle
//           nearest its centroid) and the element's index.
//   Cost: linear in the refined mesh (one Dijkstra): about 7 ms of a valid
//   layout at 30K triangles (the handle), 1.3 ms of an invalid one.
#pragma once

#include "stripweave/core/types.h"

#include <cstdint>
#include <vector>

namespace stripweave {

struct Surface;
struct LoopArrangement;
struct QuadLayout;

constexpr double kDegenerateArea = 1e-4;   // of the surface's area
constexpr double kDegenerateRadius = 2.0;  // mean solver edge lengths
// A narrow patch is forced by the part when its inradius is at least this
// share of its crease width (the largest distance of its vertices from a
// crease or the open boundary): both are graph distances on the same refined
// mesh, equal where the patch spans its face from crease to crease, and the
// share allows for the refined mesh's detours near the patch's corners.
constexpr double kForcedWidth = 0.9;
constexpr int kMaxFreeValence = 6;

enum class DefectKind : std::uint8_t {
  NonQuad, OverlappingEdges, Valence2, HighValence, Creased, Degenerate, Uncovered
};

// "non_quad", "overlapping_edges", "valence2", "high_valence", "creased",
// "degenerate", "uncovered".
const char* defect_name(DefectKind kind);

struct DefectLocation {
  DefectKind kind = DefectKind::NonQuad;
  Vec3 position = Vec3::Zero();  // model units, on the surface
  Index patch = kInvalid, vertex = kInvalid;
  Index edge = kInvalid, other_edge = kInvalid;  // overlapping_edges: the pair (equal when an edge meets itself)
  Index triangles = 0;  // uncovered: surface triangles in this piece
};

struct LayoutDefects {
  Index non_quad_patches = 0, overlapping_edges = 0, valence2_vertices = 0, high_valence_vertices = 0,
        creased_patches = 0, degenerate_patches = 0, uncovered_triangles = 0;
  std::vector<std::vector<DefectKind>> patch_defects, vertex_defects, edge_defects;  // per element
  std::vector<double> patch_inradius;  // per patch, normalized units
  std::vector<int> vertex_forced_valence;  // per primal vertex: the n of the valence rule (0 off corners)
  std::vector<DefectLocation> locations;

  bool any() const {
    return non_quad_patches + overlapping_edges + valence2_vertices + high_valence_vertices + creased_patches +
               degenerate_patches + uncovered_triangles > 0;
  }
};

LayoutDefects find_layout_defects(const Surface& surface, const LoopArrangement& arrangement,
                                  const QuadLayout& layout, const std::vector<std::uint8_t>& crease = {});

}  // namespace stripweave
