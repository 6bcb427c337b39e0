// Patch parameterization: a harmonic map of a quad patch's triangle mesh
// onto the unit square.
//
// Input   a NetworkPatch (patch_network.h): a disc triangle mesh whose
//         boundary is its 4 sides' polylines, corners[i] at the start of
//         side i, counter-clockwise seen from outside.
// Output  per patch-mesh vertex its (u, v) in [0, 1]^2, and per side the
//         mesh vertices along it with their arc-length parameter.
// Method  The boundary is pinned: corner i goes to square corner i
//         ((0,0), (1,0), (1,1), (0,1)) and the vertices along each side are
//         spread by normalized arc length (chord length of the polyline),
//         the same parameter the side's edge curve is fitted with, so the
//         surface side and the edge curve agree point for point. The
//         interior solves the discrete Laplace equation with cotangent
//         weights (Pinkall-Polthier), each clamped from below to a small
//         positive fraction of the mean: with positive weights and a convex
//         boundary polygon the map is a bijection (Tutte/Floater), so a bad
//         (obtuse) triangle only costs a little harmonicity, never a fold.
//         One sparse Cholesky solve (Eigen SimplicialLDLT) for u and v.
// Errors  InputError when the mesh is not a disc with one boundary loop, or
//         the corners are not on it in counter-clockwise order.
#pragma once

#include "stripweave/surfacing/patch_network.h"

namespace stripweave {

struct PatchParameterization {
  std::vector<Vec2> uv;                         // per patch-mesh vertex
  std::array<std::vector<Index>, 4> side_vertices;  // side i: corners[i] .. corners[i+1]
  std::array<std::vector<double>, 4> side_t;        // their normalized arc length
};

PatchParameterization harmonic_square_map(const NetworkPatch& patch);

}  // namespace stripweave
