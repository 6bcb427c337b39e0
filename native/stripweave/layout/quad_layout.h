// Primalization (paper §7): the quad layout that a valid set of dual loops
// implies, embedded in the refined mesh of their arrangement.
//
// build_quad_layout(surface, arrangement, regions, singularities, pins,
//                   symmetries, routes) -> QuadLayout
//   Input : the surface; the loops' arrangement (loop_arrangement.h) and its
//           regions (regions.h), computed with the same singularities
//           (cross_field.h); pins: points (normalized units) where the user
//           put primal vertices (§7: dragged within their regions), none by
//           default; symmetries: the reflections and rotations the design
//           accepted (paper §5.8; normalized units), none by default;
//           routes: primal edges the user drew through points of their
//           corridors (§7, manual; EdgeRoute), none by default.
//   Structure (fixed by the loops): one primal vertex per region, one primal
//           edge per arc (a loop's piece between crossings) joining the
//           regions on its two sides, one quad patch per crossing bounded by
//           the edges of its four arc-ends. Only a valid design (no red
//           region) has a layout; otherwise the result is empty.
//   Geometry (proposed, as the paper's assistance; primal_*.cpp):
//     vertices  primal_vertices.cpp: in order of preference a corner of the
//               region (a boundary corner, or where three or more sharp
//               feature curves meet), a point on the open boundary if the
//               region touches it, a point on a sharp feature curve
//               running through the region (where the region's sides
//               balance, among its points at least a quarter of the
//               region's inradius from the loops), the region's single
//               cross-field singularity (unless it is closer to the loops
//               than half the region's inradius), else its balanced centre:
//               the point with the least sum of squared distances to its
//               sides, where the corridors' middles cross
//               (primal_vertex_balance.cpp), among the points at least half
//               the inradius from the loops. A boundary vertex also goes
//               where the sides balance. A pin then moves its region's
//               vertex to the region's point nearest the pin, among the
//               points the rules allow there: on the boundary for a
//               boundary region, on the crease for a region carrying one,
//               and nowhere for a corner of the part, which stays.
//               Under symmetries, regions that are images of each other
//               get vertices that are images of each other: one
//               representative per orbit keeps its vertex (a pinned region
//               if the orbit has one: its images get the mapped pin), the
//               others take its image, snapped to their points the same
//               rules allow; a region that is its own image gets a point
//               of the plane or axis where the rules allow one
//               (primal_vertex_symmetry.cpp).
//     edges     primal_edges.cpp: shortest paths in the region cut open along
//               the loops (each region's shortest-path tree from its vertex,
//               so edges leaving a vertex never cross; edges of different
//               regions meet only where they cross their arc), with sharp
//               an edge across an arc that a crease crosses (a crease
//               exit of both regions) IS the crease chain from one vertex
//               over the exit to the other, and is never re-routed; other
//               edges have sharp
//               feature and open-boundary edges made cheap so that a primal
//               edge whose corridor holds a crease or the boundary follows
//               it. The edge crosses its arc once, where the two trees'
//               distances sum to the least. Edges that would share vertices
//               are re-routed apart (one after another, then ripping up
//               the edges that close a corridor: primal_edges.cpp). An
//               edge routed by hand (routes: EdgeRoute, below) is the
//               shortest corridor path through the user's point, routed
//               before the others, which keep clear of it; then the zig-zag of the mesh-edge paths
//               is relaxed on the surface (primal_straightening.cpp).
//               Where routed edges still share vertices, the mesh is too
//               coarse for them (a vertex of valence 7 or more has about
//               6 neighbours; a corridor can be one vertex wide): the
//               refined mesh is refined around the crowded vertices
//               (primal_vertex_stars.cpp, star_refinement.h) and the edges
//               are routed again, up to kStarRounds times; the primal
//               vertices stay where they are. A layout whose edges never
//               share a vertex is not refined.
//               A region whose creases form a star (crease_structure.h)
//               takes its vertex at the star's node (a crease junction, end
//               or boundary meeting), or on the crease when it has none.
//     patches   primal_patches.cpp: the refined mesh cut along the primal
//               edges; each piece holds one crossing, and its boundary is
//               read as four sides (edge runs) between four corners.
//   Output (normalized units): see QuadLayout, embedded in the arrangement
//           and regions as they are on return: refined in place around
//           crowded vertices (above), unchanged where no vertex is crowded. `problems` lists what keeps
//           the embedding from being a clean quad layout (a patch without
//           four sides, two edges sharing a stretch); the structure is
//           still reported. `defects` holds the strict checks of the result
//           (layout_defects.h).
#pragma once

#include "stripweave/layout/cut_wedges.h"
#include "stripweave/strips/edge_route.h"
#include "stripweave/layout/layout_defects.h"
#include "stripweave/layout/regions.h"
#include "stripweave/surface/creases.h"
#include "stripweave/symmetry/symmetry.h"

#include <array>
#include <string>

namespace stripweave {

enum class VertexPlacement : std::uint8_t { Corner, Boundary, Feature, Singularity, Centre, Pinned };

struct PrimalVertex {
  Index region = kInvalid;
  Index refined_vertex = kInvalid;  // in the arrangement's refined mesh
  Vec3 position = Vec3::Zero();     // normalized units
  int valence = 0;                  // primal edge ends at it
  bool boundary = false;            // on the open boundary
  VertexPlacement placement = VertexPlacement::Centre;
  // Distance from the loops within its region, and the region's largest
  // (its inradius), normalized units: how centred the vertex sits.
  double clearance = 0, inradius = 0;
  // The vertex (region) whose vertex this one is the symmetric image of
  // (primal_vertex_symmetry.cpp); kInvalid for an orbit's representative
  // and without symmetries.
  Index image_of = kInvalid;
  // The pins (indices among the layout's pins) that lie in its region, by
  // pin_primal_vertices' rule (the last of them places the vertex, unless
  // the vertex is a corner of the part): an editor moving this vertex
  // replaces them, so that editor and layout agree on which pin is whose.
  std::vector<Index> pins;
};

struct PrimalEdge {
  Index arc = kInvalid;          // the arc it is dual to
  Index v0 = kInvalid, v1 = kInvalid;  // primal vertices: left and right region of the arc
  std::vector<Index> path;       // refined vertices from v0's to v1's
  Index crossing = 0;            // position in `path` where it crosses its arc
  bool sharp = false;            // runs on sharp feature curves (most of its length)
  bool boundary = false;         // runs on the open boundary
  double length = 0;             // normalized units
  Index through = kInvalid;      // refined vertex a hand route (EdgeRoute) takes it through
  // The hand route that names this edge (its index among the layout's
  // EdgeRoutes; resolve_edge_routes' rule, the last of several), whether the
  // edge took it or refused it (an edge on a crease keeps the crease);
  // kInvalid if none. An editor replaces this route when the edge is
  // re-routed, so that editor and layout agree on which route is whose.
  Index route = kInvalid;
};

struct PrimalPatch {
  Index node = kInvalid;               // the arrangement node (crossing) it holds
  std::array<Index, 4> edges{kInvalid, kInvalid, kInvalid, kInvalid};  // counter-clockwise from outside
  std::array<bool, 4> reversed{false, false, false, false};  // side i runs from v1 to v0
  std::array<Index, 4> corners{kInvalid, kInvalid, kInvalid, kInvalid};  // primal vertex starting side i
  std::array<double, 4> corner_angle{0, 0, 0, 0};  // radians, between the sides at each corner
  std::array<Index, 4> corner_wedges{kInvalid, kInvalid, kInvalid, kInvalid};  // in QuadLayout::patch_wedges
  std::vector<Index> triangles;        // refined triangles
  double area = 0;                     // normalized units squared
  bool quad = false;                   // its boundary reads as exactly four sides
  // Length of the creases (sharp feature edges the layout follows) inside the
  // patch, not on its sides, normalized units: a patch laid over a crease,
  // which no smooth patch fits.
  double crease_length = 0;
  // Over a crease: more than kCreasedPatchLength of it inside (creases.h).
  bool creased() const { return crease_length > kCreasedPatchLength; }
  // A side comes straight back along the side before it (the same edge, run
  // the other way): the patch folds around a slit, no quad (layout_defects.h).
  bool folds_back() const {
    for (int k = 0; k < 4; ++k) {
      const int next = (k + 1) % 4;
      if (edges[next] != kInvalid && edges[next] == edges[k] && reversed[next] != reversed[k]) return true;
    }
    return false;
  }
};

struct QuadLayout {
  bool valid = false;  // the design is valid (no red region): the layout exists
  std::vector<PrimalVertex> vertices;
  std::vector<PrimalEdge> edges;
  std::vector<PrimalPatch> patches;
  std::vector<Vec3> positions;        // per refined vertex, after straightening the edges (normalized)
  std::vector<Index> triangle_patch;  // per refined triangle, kInvalid outside every patch
  Wedges patch_wedges;                // the refined mesh cut open along the primal edges
  std::vector<std::string> problems;
  // Crease conformity (issue 17; primal_crease_conformity.cpp): the crease
  // length lying on primal edges over the whole crease length (1 without
  // creases; 0 for an invalid layout with creases), the crease length off
  // them (normalized units), and whether the layout is crease-conforming: no
  // region is crease-coloured and no more than kCreaseSlack of crease length
  // lies off the primal edges.
  double crease_conformity = 1.0;
  double crease_off_edges = 0;
  bool crease_conforming = true;
  // The strict checks (layout_defects.h), also of an invalid layout (whose
  // every surface triangle is uncovered).
  LayoutDefects defects;
};

constexpr double kCreaseSlack = 1e-6;  // of the bounding-box diagonal

// Star refinements before the edges' routes stand: each round can double a
// crowded vertex's neighbours (three take 6 to as many as 48), and a
// corridor that three rounds do not open is blocked by the loops, not by
// the mesh.
constexpr int kStarRounds = 3;

QuadLayout build_quad_layout(const Surface& surface, LoopArrangement& arrangement, Regions& regions,
                             const std::vector<Singularity>& singularities, const std::vector<Vec3>& pins = {},
                             const std::vector<Symmetry>& symmetries = {}, const std::vector<EdgeRoute>& routes = {});

}  // namespace stripweave
