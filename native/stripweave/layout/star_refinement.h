// Star refinement: more neighbours for a crowded primal vertex (paper §7).
//
// The primal edges at a vertex are paths of refined edges that may share
// nothing but their ends, so each leaves the vertex through a neighbour of
// its own. A vertex of valence k needs k neighbours, and a solver mesh gives
// a vertex about six: a region of valence 7 or more cannot be cut into its
// patches at a vertex of the mesh as it is, and even fewer free neighbours
// than edges make the edges crowd each other where they leave. Refining the
// mesh around the vertex, not moving it, keeps the placement's reasons
// (centre, corner, crease, pin, symmetry) and changes only the corridors.
//
// refine_stars(surface, arrangement, regions, centres) -> edges split
//   Input : the arrangement (loop_arrangement.h) and its regions (regions.h);
//           refined vertices off the loops (the crowded vertices).
//   Method: every edge of a centre's link (the side of each of its triangles
//           opposite it) that lies on no loop, on no open boundary and on no
//           crease is split at its midpoint, and each triangle on a split
//           edge is cut through the new vertex (a triangle with two or three
//           split sides into three or four). A centre with d triangles so
//           gains up to d neighbours; the link edges it keeps are the ones
//           the layout must keep whole (loops and creases are where primal
//           edges end or run).
//   Output: the arrangement and regions, refined in place. Vertex and
//           triangle indices are kept: new vertices and triangles are
//           appended, and a cut triangle keeps its index for one of its
//           pieces. Edges are renumbered, and every per-edge array follows
//           (loop labels, chains, arcs, refined creases); an arc's left and
//           right triangles are those of its first edge again. A new vertex
//           lies in the surface triangle (and surface edge) of the edge it
//           splits; a piece lies in the surface triangle and region of the
//           triangle it was cut from. Linear in the mesh (the topology is
//           rebuilt).
#pragma once

#include "stripweave/layout/loop_arrangement.h"
#include "stripweave/layout/regions.h"

#include <vector>

namespace stripweave {

Index refine_stars(const Surface& surface, LoopArrangement& arrangement, Regions& regions,
                   const std::vector<Index>& centres);

}  // namespace stripweave
