// patch_grid: a fitted B-spline patch densely sampled on a (u, v) grid, for
// measuring the fit (fit_deviation.h).
//
// Input   a BSplinePatch, the largest sample spacing (model units), the
//         largest chordal error allowed at a grid triangle's centroid
//         (model units), and the samples per span.
// Output  PatchGrid: (nu_samples + 1) x (nv_samples + 1) grid nodes on the
//         patch with their (u, v) and area weights (|Su x Sv| du dv, halved
//         on the border: the trapezoid rule), and the grid's triangles (two
//         per cell), whose vertices lie exactly on the patch.
// Method  nu_samples = per_span * nu, but at least control-row length /
//         spacing (a control polygon is at least as long as its curve), likewise
//         in v (a cap at a quarter of the spacing missed a span-scale bulge of
//         handle.step's fit: 0.085 reported where FreeCAD measures 0.121);
//         while the largest distance between a triangle's flat centroid and
//         the patch point at its centroid's (u, v) exceeds `chord`, both
//         counts grow by the square root of the excess (chordal error ~ h^2),
//         up to kMaxGridSamples per direction (chord <= 0: no such check;
//         max_chord is measured all the same). Why `per_span`: a fit's error
//         oscillates at most about twice per span, so with 8 samples per span
//         the largest sampled deviation is within 1 - cos(pi / 8) (8 %) of the
//         largest between the samples.
#pragma once

#include "stripweave/surfacing/bspline.h"

namespace stripweave {

constexpr int kMaxGridSamples = 200;

struct PatchGrid {
  int nu = 0, nv = 0;           // cells along u and v
  std::vector<Vec2> uv;         // per node, index i * (nv + 1) + j
  std::vector<Vec3> points;     // per node, on the patch
  std::vector<double> weight;   // per node, its share of the patch area
  std::vector<Tri> triangles;   // node indices
  double max_chord = 0;         // largest centroid chordal error of the triangles
};

PatchGrid patch_grid(const BSplinePatch& patch, double spacing, double chord, int per_span = 8);

// The nodes of patch_grid(patch, spacing, 0, per_span) (uv, points and
// weights) without its triangles: samples to measure from, at two thirds of
// the memory (the deviation holds them for every patch at once).
PatchGrid patch_sample_grid(const BSplinePatch& patch, double spacing, int per_span = 8);

// The grid of exactly nu x nv cells (each at least 1), its max_chord measured.
PatchGrid patch_grid_of_size(const BSplinePatch& patch, int nu, int nv);

}  // namespace stripweave
