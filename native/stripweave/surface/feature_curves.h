// Feature curves and boundary classification of mesh edges (paper §5.6, §5.7).
//
// classify_edges(mesh, topo, is_feature) -> per-edge classes
//   Boundary for edges with one triangle, Feature where is_feature[e] holds,
//   Regular otherwise.
//
// chain_feature_curves(mesh, topo, classes, break_vertex, min_length)
//   Chains the Feature edges into curves. A chain ends where the number of
//   feature edges at a vertex is not two (a corner or an end), or at a vertex
//   with break_vertex[v] (e.g. a B-rep vertex where one CAD edge meets the
//   next). Chains joined at their ends form a crease cluster; a cluster
//   shorter in total than min_length (in the mesh's units) is scan noise (a
//   spike, a scratch) and is dropped: its edges become Regular. Returns the curves and fills edge_curve (curve id or
//   kInvalid per edge).
//
// dihedral_feature_edges(mesh, topo, angle_deg) -> per-edge flag
//   Interior edges whose dihedral angle (between the two triangle normals)
//   exceeds angle_deg.
#pragma once

#include "stripweave/surface/surface.h"

namespace stripweave {

std::vector<EdgeClass> classify_edges(const MeshTopology& topo, const std::vector<bool>& is_feature);

std::vector<FeatureCurve> chain_feature_curves(const TriangleMesh& mesh, const MeshTopology& topo,
                                               std::vector<EdgeClass>& classes, const std::vector<bool>& break_vertex,
                                               double min_length, std::vector<Index>& edge_curve);

std::vector<bool> dihedral_feature_edges(const TriangleMesh& mesh, const MeshTopology& topo, double angle_deg);

}  // namespace stripweave
