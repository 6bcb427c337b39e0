// Principal curvatures and directions of a triangle mesh by jet fitting
// (CGAL Monge_via_jet_fitting, Cazals & Pouget 2005).
//
// Inputs
//   mesh     clean, consistently oriented manifold mesh (outward normals)
//   radius   neighbourhood radius, in the mesh's units: every vertex within
//            this Euclidean distance that is reachable through the mesh from
//            the centre vertex takes part in the fit. It is a growing ring, so
//            the other side of a thin part is never used; nor does the ring
//            cross vertices whose normal is more than 90 degrees from the
//            centre's, so it cannot turn round the rim of a part thinner than
//            the radius either. At least `min_neighbours` vertices are used:
//            the ring grows further when the ball holds fewer.
// Outputs (per vertex)
//   normal            unit normal of the fitted jet, oriented like the
//                     area-weighted vertex normal of the mesh
//   k_min <= k_max    principal curvatures, positive where the surface is
//                     convex (bends away from the outward normal, as on a
//                     sphere: k = +1/R)
//   d_min, d_max      unit principal directions, tangent to `normal`
//
// A degree-2 jet is fitted (a quartic on neighbourhoods this small is
// ill-conditioned). A vertex whose fit fails (too few or degenerate points, or
// a fitted normal more than ~75 degrees off the mesh's) is refitted on larger
// neighbourhoods, then on its 10 nearest vertices; if none works (isolated
// vertex, tiny component) it is reported flat (k = 0) with the mesh normal,
// so the output never holds NaN. Scaling the radius with the model, not with the edge
// length, keeps scan noise from swamping the principal directions.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

namespace stripweave {

struct CurvatureField {
  std::vector<Vec3> normal;  // per vertex
  std::vector<double> k_min, k_max;
  std::vector<Vec3> d_min, d_max;
};

CurvatureField jet_fit_curvature(const TriangleMesh& mesh, double radius, int min_neighbours = 16);

}  // namespace stripweave
