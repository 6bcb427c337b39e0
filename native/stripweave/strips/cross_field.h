// The 4-RoSy cross field of a design (paper §6.1).
//
// compute_cross_field(surface, constraints, options) -> CrossField
//   Input : the surface; per-triangle direction constraints (the loops'
//           segments, path_segments.h); options saying whether feature
//           curves and open boundaries constrain the field too (beyond the
//           paper: on CAD parts the patches must follow the creases).
//   Method: one representation vector u_t = exp(4 i theta_t) per triangle,
//           theta_t measured in the triangle's frame (frame_x, normal x
//           frame_x). Constrained triangles are fixed to their direction
//           (several constraints in one triangle are averaged as
//           representation vectors); the rest is harmonic:
//             minimize sum over interior edges e=(t0,t1) of
//               |u_t1 - exp(4 i rho_e) u_t0|^2,
//           rho_e being the rotation from t0's frame to t1's across e (the
//           discrete Levi-Civita connection), plus a weak prior towards the
//           principal curvature directions, weighted by the squared
//           anisotropy (options.curvature; it keeps the field from wandering
//           far from the constraints, and it is what fixes the field on a
//           component without constraints; an umbilic one gets the
//           smoothest unit field instead). One sparse Hermitian solve.
//   Output (indexed by element):
//     frame_x[t]     unit tangent of triangle t's frame
//     normal[t]      unit normal of that frame (the frame's y is normal x frame_x)
//     theta[t]       the field's angle in that frame (one of four, in [0, pi/2))
//     direction[t]   the unit 3D vector at theta[t]
//     strength[t]    |u_t| in [0,1]: 1 where constrained, small near singularities
//     constrained[t] 1 if the triangle was constrained
//     rho[e]         the connection across edge e, from edge_triangles[e][0]'s
//                    frame to [1]'s (0 on boundary edges)
//     matching[e]    r in {0,1,2,3}: theta[t1] ~ theta[t0] + rho[e] + r pi/2
//     singularities  vertices of non-zero index, index = quarter_index / 4.
//                    Index of v = (A(v) + sum of the field's jumps across the
//                    edges around v, relative to those edges) / 2 pi, with
//                    A(v) the angle defect (pi - angle sum on the boundary),
//                    so the indices sum to the Euler characteristic
//                    (Poincaré–Hopf) by discrete Gauss–Bonnet.
//     solve_ms       assembly and solve time
// Throws InputError if the surface has no triangles.
#pragma once

#include "stripweave/strips/path_segments.h"

#include <complex>

namespace stripweave {

struct FieldConstraint {
  Index triangle = kInvalid;
  Vec3 direction = Vec3::Zero();  // tangent (projected onto the triangle), any length > 0
};

struct FieldOptions {
  bool features = true;  // feature curves constrain their triangles
  bool boundary = true;  // open boundaries constrain their triangles (aligned mode)
  double curvature = 1.0;  // weight of the principal-direction prior, 0: purely harmonic (cross_field.cpp)
};

struct Singularity {
  Index vertex = kInvalid;
  int quarter_index = 0;  // index = quarter_index / 4
  double index() const { return quarter_index / 4.0; }
};

struct CrossField {
  std::vector<Vec3> frame_x;
  std::vector<Vec3> normal;
  std::vector<double> theta;
  std::vector<Vec3> direction;
  std::vector<double> strength;
  std::vector<std::uint8_t> constrained;
  std::vector<double> rho;
  std::vector<std::int8_t> matching;
  std::vector<Singularity> singularities;
  double solve_ms = 0;

  // The field's direction in triangle t turned by r quarter turns (about the
  // triangle normal, counter-clockwise).
  Vec3 direction_turned(const Surface& surface, Index t, int r) const;
};

CrossField compute_cross_field(const Surface& surface, const std::vector<FieldConstraint>& constraints,
                               const FieldOptions& options = {});

// Field constraints from the segments of embedded loops.
std::vector<FieldConstraint> loop_constraints(const std::vector<std::vector<PathSegment>>& loops);

}  // namespace stripweave
