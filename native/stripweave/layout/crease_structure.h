// The creases of the part seen from the regions of a loop arrangement
// (issue 17): can the primal layout the loops imply be crease-conforming?
//
// A layout is crease-conforming when the crease network (creases.h) is a
// subgraph of the primal edge graph: every crease junction, crease end and
// point where a crease meets the open boundary is a primal vertex, every
// crease arc is a chain of primal edges, and no patch interior meets a
// crease. Dually, each region holds one primal vertex and sends one primal
// edge across each of its arcs, so a region can carry its creases exactly
// when they form a STAR around one point:
//   - its crease pieces (the refined crease edges inside it, cut at the
//     loops) are connected and hold no cycle;
//   - at most one NODE lies in it: a crease junction (3 or more crease edges),
//     a crease end, or a point where a crease meets the open boundary; the
//     primal vertex goes there, or anywhere on the crease when there is none;
//   - every other end of the star is an EXIT: the crease crosses a loop at a
//     point of an arc, not at a loop crossing, and no two exits share an arc
//     (each arc has one primal edge);
//   - no loop runs along a crease (the crease would lie on no primal edge);
//   - a region touching the open boundary carries a crease only if the
//     crease meets the boundary inside it (its vertex must be on the
//     boundary, so the boundary's primal edges reach it, and on the crease).
// From each side a crease then behaves like an aligned open boundary (§5.7):
// curves cross it and primal edges follow it; the two sides match because
// the primal edge across an arc is the crease chain from one region's vertex
// over the exit to the other's.
//
// refined_crease_edges(surface, arrangement) -> per refined edge, 1 if it
//   lies on a crease of the surface.
// crease_structure(surface, arrangement, triangle_region, regions)
//   Input : the surface (its Feature edges are the creases), the arrangement,
//           the region of each refined triangle and the number of regions.
//   Output: per region the problem that keeps it from conforming (None when
//           it can), its node (refined vertex, or kInvalid) and whether it
//           holds crease pieces, and for a region with a problem the point
//           where a loop crossing the crease would resolve it (split_vertex:
//           automatic weaving seeds there); the rims' lack of crossings
//           and their seeds, each at the region its seed lies in
//           (crease_rims.h); per arc the refined vertex where a crease
//           exits across it (kInvalid if none, or if several); per refined
//           edge whether it is a crease.
//   Cost  : linear in the refined mesh.
#pragma once

#include "stripweave/layout/loop_arrangement.h"

#include <cstdint>

namespace stripweave {

enum class CreaseProblem : std::uint8_t {
  None = 0,
  TwoNodes,       // two crease junctions, ends or boundary meetings in one region
  Disconnected,   // crease pieces that do not meet in one point
  Cycle,          // a closed crease (or a crease cycle) inside the region
  SameArc,        // the crease leaves twice across one arc
  OnCrossing,     // a loop crossing lies on a crease
  AlongLoop,      // a loop runs along a crease
  BoundaryApart,  // the region touches the boundary, its crease does not
  RimUncrossed,   // a rim whose seed lies in the region is crossed fewer than twice (crease_rims.h);
                  // Region::crease_problem only, where the star test finds none
};

// "two crease nodes", "crease pieces apart", ... (a phrase for messages and JSON).
const char* crease_problem_name(CreaseProblem problem);

struct RegionCreases {
  CreaseProblem problem = CreaseProblem::None;
  Index node = kInvalid;      // refined vertex of the junction, end or boundary meeting
  bool has_crease = false;    // crease pieces lie inside the region
  Index problem_vertex = kInvalid;  // a refined vertex where the problem shows (for locations)
  // Where a loop would resolve the problem: the middle (by length) of the
  // crease path between the two nodes, or between the two exits across one
  // arc; for pieces apart, the middle of the shortest bridge between two of
  // them inside the region (region_bridges.h); else problem_vertex.
  Index split_vertex = kInvalid;
  // The direction across that path there (unit, normalized frame; zero when
  // the split is on no such path): the loop that resolves the region leaves
  // split_vertex this way (across a crease path it parts the two nodes;
  // across a bridge it runs between the two pieces).
  Vec3 split_across = Vec3::Zero();
  // How far the region is from carrying its creases, in one count that every
  // separating loop lowers: nodes beyond one, crease pieces beyond one, exits
  // beyond one per arc, independent crease cycles, and one each for a loop
  // crossing or a loop along the crease and for a crease apart from the
  // boundary. 0 iff problem is None.
  int excess = 0;
  // The crossings the rims lack whose seed lies in the region (crease_rims.h;
  // a rim's lack counts once, at its seed). Where the star test finds no
  // problem, split_vertex and split_across are then the first such rim's
  // seed and its direction across the rim.
  int rim_lack = 0;
};

struct CreaseStructure {
  std::vector<std::uint8_t> refined_crease;  // per refined edge
  std::vector<RegionCreases> regions;        // per region
  std::vector<Index> arc_exit;               // per arc: the refined vertex a crease crosses it at
};

std::vector<std::uint8_t> refined_crease_edges(const Surface& surface, const LoopArrangement& arrangement);

CreaseStructure crease_structure(const Surface& surface, const LoopArrangement& arrangement,
                                 const std::vector<Index>& triangle_region, Index num_regions);

}  // namespace stripweave
