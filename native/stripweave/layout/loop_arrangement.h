// The arrangement of a design's dual loops on the surface (paper §4.2, §7):
// the loops embedded exactly as edges of a refined copy of the mesh.
//
// build_loop_arrangement(surface, loops) -> LoopArrangement
//   Input : the surface (normalized units); the design's dual loops and open
//           dual curves, each as its embedded SurfacePath (points at mesh
//           vertices or inside mesh edges, with (edge, t)) and closed flag.
//           The per-triangle segments of a LoopPath are not needed: the
//           steps are re-derived after snapping (below), which may turn a
//           step into a run along a mesh edge.
//   Method: (1) Snapping. The points inside each surface edge, of all loops
//           together, are sorted by t; a point within kSnap (1e-6) of the
//           edge's length from an end becomes that vertex, and points within
//           kSnap of each other become one point (where loops meet on the
//           edge). The loops are accurate to about 1e-9 of the model, so
//           this moves nothing visible, and it keeps every piece of the
//           refinement at least 1e-6 of an edge long. Steps that snapping
//           shrinks to nothing are dropped.
//           (2) Steps. Each remaining step of a loop either runs along a
//           surface edge (its two points lie on one closed edge: the loop
//           then follows that edge's refined pieces) or is a straight chord
//           of the one triangle whose boundary holds both points. Anything
//           else is not an embedded path (InputError).
//           (3) Refinement. Every triangle with chords or with points on its
//           sides is cut by its chords (chord_split.h: exact combinatorial
//           crossings, crossings within kSnap of the triangle's size merged,
//           convex pieces fanned without flat triangles); crossings inside a
//           triangle, also of a loop with itself, become vertices. The
//           pieces are welded along the surface edges through the shared
//           snapped points, so the refined mesh is a manifold with the
//           surface's topology (same Euler characteristic). Other triangles
//           are copied.
//           (4) Chains, arcs, nodes. Each loop becomes a chain of refined
//           edges, and each of those edges a label (loop, position in the
//           chain, path step, direction). The arrangement graph is made of
//           the loop edges and the open-boundary edges; its nodes are the
//           vertices where its degree is not 2: crossings (loops meeting,
//           also a loop meeting itself, or loops touching), ends of open
//           curves (on the boundary), and where loops touch the boundary. A
//           loop's arcs are its pieces between consecutive nodes; a loop
//           meeting nothing is one closed arc.
//           (5) Bare arcs. An arc that is a single chord piece from node to
//           node (three loops nearly concurrent in one triangle) has no
//           inner vertex for its primal edge to cross it at: its piece is
//           split at its midpoint and (4) is made again.
//   Output (normalized units): see LoopArrangement. Cost: linear in the
//           surface plus the loops' length; a few ms at 30K triangles.
#pragma once

#include "stripweave/strips/parameterization.h"

namespace stripweave {

// Points closer than this (relative to the length of their edge, or to the
// size of their triangle for crossings) are one point.
constexpr double kSnap = 1e-6;

// A refined edge's place on a loop.
struct LoopLabel {
  Index loop = kInvalid;
  Index position = kInvalid;  // index of the edge in the loop's chain (LoopChain::edges)
  Index step = kInvalid;      // the path step it lies on: from path point `step` to the next one
  bool forward = true;        // the loop runs from topology.edges[e][0] to [1]
};

// A loop drawn on the refined mesh.
struct LoopChain {
  std::vector<Index> vertices;  // in the order of travel; a closed chain does not repeat its first
  std::vector<Index> edges;     // edges[i] joins vertices[i] and vertices[i + 1] (wrapping when closed)
  bool closed = true;
};

// A piece of one loop between two consecutive nodes of the arrangement.
struct LoopArc {
  Index loop = kInvalid;
  std::vector<Index> vertices;  // refined vertices from node to node (a closed arc does not repeat its first)
  std::vector<Index> edges;     // edges[i] joins vertices[i] and vertices[i + 1]
  bool closed = false;          // the whole loop, which meets no node
  // The refined triangles left and right of the arc's first edge (in its
  // direction of travel, seen from outside); kInvalid on an open boundary.
  Index left_triangle = kInvalid, right_triangle = kInvalid;
};

// A vertex of the arrangement graph.
struct ArrangementNode {
  Index vertex = kInvalid;   // refined vertex
  Index degree = 0;          // loop and open-boundary edges at it
  Index passes = 0;          // times loops pass through it (an open curve's end is one pass)
  std::vector<Index> arcs;   // the arcs starting or ending here (an arc doing both is listed twice)
  bool crossing() const { return passes >= 2; }
};

struct LoopArrangement {
  TriangleMesh mesh;  // refined, normalized units, counter-clockwise like the surface
  MeshTopology topology;
  std::vector<Index> parent_triangle;  // per refined triangle: the surface triangle it lies in
  std::vector<Index> original_vertex;  // per refined vertex: the surface vertex it is, or kInvalid
  std::vector<Index> original_edge;    // per refined vertex inside a surface edge: that edge, else kInvalid
  Csr edge_labels;                     // per refined edge: indices into `labels`; none off the loops
  std::vector<LoopLabel> labels;
  std::vector<Index> degree;           // per refined vertex: loop and open-boundary edges at it
  std::vector<LoopChain> chains;       // per input loop (empty if snapping left fewer than two points)
  std::vector<LoopArc> arcs;
  std::vector<ArrangementNode> nodes;
  Index crossings = 0;                 // nodes where two or more loop passes meet
  // The arrangement graph (loop arcs and open-boundary pieces); a cycle with
  // no node (a loop meeting nothing, a boundary loop no curve ends on)
  // counts as one vertex and one edge.
  Index graph_vertices = 0, graph_edges = 0;
  Index snapped_points = 0;  // loop points that snapping moved
  Index star_triangles = 0;  // triangles cut by the fallback of chord_split.h

  bool on_loop(Index e) const { return edge_labels.size(e) > 0; }
  // A region boundary: a loop edge or an open-boundary edge.
  bool separates(Index e) const { return on_loop(e) || topology.is_boundary_edge(e); }
};

LoopArrangement build_loop_arrangement(const Surface& surface, const std::vector<LoopPath>& loops);

}  // namespace stripweave
