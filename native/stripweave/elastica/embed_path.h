// Embedding a chain of g-edges on the surface (paper §5.3: g-edges are
// surface geodesics; later stages cut the mesh along the result).
//
// embed_path(surface, graph, nodes, closed) -> SurfacePath
//   Traces each g-edge (v->w) of the chain as a geodesic across the triangles
//   from vertex v to vertex w, in v's local geodesic map, and concatenates
//   them. For a closed chain the path returns to its first point.
// SurfacePath (normalized units)
//   points[i]    on the surface: a mesh vertex or a point on a mesh edge
//   vertex[i]    the mesh vertex at points[i], or kInvalid
//   edge[i], t[i]  for a point inside a mesh edge: the edge id and the
//                parameter t in (0,1) from edges[edge][0] to edges[edge][1];
//                kInvalid / 0 at vertices
//   node_start[j]  index into points of the start of the j-th g-edge
// The polyline is smooth (no zig-zag): it follows the straight segment of the
// local map, not mesh edges; inside a g-edge it bends only with the surface.
// Where a map folds (about 1 g-edge in 5000 on noisy scans) a g-edge may
// instead be embedded in halves meeting at a vertex, or, as the last resort,
// along mesh edges. Cost: one local map per g-edge, about 30 us each.
// Throws std::invalid_argument for node ids out of range, consecutive nodes
// that do not share a vertex, or a closed chain that does not return.
#pragma once

#include "stripweave/elastica/elastica_graph.h"

namespace stripweave {

struct SurfacePath {
  std::vector<Vec3> points;
  std::vector<Index> vertex;
  std::vector<Index> edge;
  std::vector<double> t;
  std::vector<Index> node_start;
};

SurfacePath embed_path(const Surface& surface, const ElasticaGraph& graph, const std::vector<Index>& nodes,
                       bool closed);

}  // namespace stripweave
