// Patch parameterization: the square map of a quad patch's triangle mesh,
// harmonic, or with its stretch spread evenly.
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
//         With NetworkPatch::even_stretch the map is then made to spread
//         the patch's area evenly over the square: rounds of reweighting
//         that divide each edge's weight by its L2 stretch (Sander et al.
//         2001) of the last map (Yoshizawa, Belyaev and Seidel 2004),
//         kept while the patch's L2 stretch falls. The harmonic map shrinks
//         a protrusion (a boss, a knob) exponentially in its height; evenly
//         spaced knots then cannot resolve it at any span count, while the
//         even map gives it its share of the square. The weights stay
//         positive, so the map stays a bijection. The fit asks for it only
//         for a patch that misses at its most spans (fit_patch_network.h):
//         the harmonic map is smoother, so its seams couple better.
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

PatchParameterization square_map(const NetworkPatch& patch);

// Only the sides: side_vertices, side_t and the boundary's uv (the interior
// uv left at 0), with the same checks; for a caller that needs the
// boundary walk and not the map (a split's cut, a piece's check).
PatchParameterization square_sides(const NetworkPatch& patch);

// How much a protrusion the harmonic map squashes: the largest L2 stretch of
// the patch's harmonic map over that of its even map (>= 1 where the even
// map spreads the patch better). Each stretch is per vertex, the RMS over its
// triangles weighted by their area on the part, so that one sliver triangle
// does not decide it.
double even_map_gain(const NetworkPatch& patch);

}  // namespace stripweave
