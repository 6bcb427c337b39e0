// Shortest bridges between the pieces of one region: where a loop must pass
// to join two of them (a cut between two boundaries of an annulus, issue 18)
// or to part them (two creases apart inside one region, issue 17).
//
// A region's PIECES are the connected sets of some of its edges: its border
// (loop and open-boundary edges) for a cut, its crease edges for a split.
// A BRIDGE of two pieces is a shortest path between them over the region's
// inner edges: it leaves one piece orthogonally and meets the other
// orthogonally, so a loop along it crosses both transversally, and a loop
// across its middle runs between them.
//
// shortest_bridges(arrangement, edges) -> the shortest bridge of each pair of
//   pieces that some shortest bridge joins, shortest first (ties: the lower
//   pair of piece labels). One Dijkstra from all pieces at once, each vertex
//   labelled with the piece nearest to it; an inner edge whose two ends carry
//   different labels closes a bridge between those pieces.
//   Input : the arrangement (its refined mesh) and the region's edges: the
//           piece edges and the inner edges (refined edge ids; an edge may be
//           in both lists).
//   Output: per bridge its length (normalized units) and its refined vertices,
//           from a vertex of one piece to a vertex of another.
//   Cost  : O(n log n) in the region's vertices.
#pragma once

#include "stripweave/layout/loop_arrangement.h"

#include <vector>

namespace stripweave {

struct RegionEdges {
  std::vector<Index> pieces;  // the edges whose connected sets are the pieces
  std::vector<Index> inner;   // the edges bridges run over
};

struct Bridge {
  double length = 0;
  std::vector<Index> path;  // refined vertices, from one piece to another
};

std::vector<Bridge> shortest_bridges(const LoopArrangement& arrangement, const RegionEdges& edges);

}  // namespace stripweave
