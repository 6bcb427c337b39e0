// fit_deviation: how far the fitted patch network is from the source, both
// ways, and how much of the source it covers (the surfacing stage's report).
//
// Input   the Surface (its source: B-rep, else source mesh), the fitted
//         patches (model units), the tolerance (model units), options.
// Output  FitDeviation (model units):
//           source -> patches  per dense source sample (source_samples.h),
//                              its distance to the nearest fitted patch;
//                              the sample belongs to that patch
//           patches -> source  per dense patch sample (patch_grid.h), its
//                              distance to the source
//         max and area-weighted RMS of each, overall and per patch;
//         coverage: the fraction of the source area whose samples lie
//         within tolerance of a patch (faces the B-rep mesher left empty
//         count as uncovered); uncovered_area; per solver-mesh triangle the
//         fraction of its source samples' area that is uncovered (each
//         sample located on the solver mesh, cgal/surface_locator.h;
//         a triangle no sample lands on takes the mean of its neighbours').
// Method  Nearest points in two steps: a CGAL AABB tree over a fine
//         tessellation (of the patch grids, of the source) finds the
//         candidate triangle, whose barycentric (u, v) starts a Newton
//         refinement on the exact geometry (distance_to_patch on the
//         B-spline; BrepSource::foot_on_face on the B-rep face; a mesh
//         source is its own tessellation, exact).
// Bound   Both tessellations have their vertices exactly on the geometry;
//         eps is the largest chordal error of their triangles (measured at
//         every triangle's centroid: to second order the largest error over
//         a triangle is at most 1.5 times its centroid's; BRepMesh's
//         boundary polygons lie within its edge deflection, 2 * chord).
//         Every reported distance is the distance to a point of the other
//         side (the foot lies on the patch's square; on the B-rep, within
//         the face's trim), so it is never below the true one. It is above
//         it only where the tessellation's nearest point lies on another
//         face or patch than the true foot point, by at most 2 eps where the
//         tessellation covers the geometry; a patch sample whose B-rep foot
//         lies farther than half the tolerance gets a second look at every
//         face whose box is nearer (the source tessellation can leave a
//         sliver of a face uncovered), so no such gap makes a fit miss.
//         `measurement_error` is that 2 eps; with the default chord
//         (tolerance / 10) it is at most 0.4 of the tolerance (0.3 away
//         from B-rep face borders), and far less in practice (Newton
//         converges on the right face or patch).
//         Sampling: the patch grids take 4 samples per span, and 8 around
//         every sample within 0.7 of its patch's largest (patch_grid.h: at 8
//         per span the sampled maximum is within 8 % of the maximum between
//         samples; at 4, within 29 %, so every bump that could top it is
//         refined); RMS figures come from the 4 per span;
//         the source samples are spaced at most `spacing` (default: the
//         solver mesh's mean edge, so one or two per solver triangle), which
//         sizes the coverage's resolution.
// Cap     The patch tessellation is capped at max_patch_triangles: a
//         network whose patches ripple (a fit far off the source, folded)
//         would otherwise need grids of 200 x 200 cells on every patch (a
//         casting's 126 patches: 7M triangles, 1.5 GB of tree). Under the
//         cap the patches that need the most cells are coarsened first (one
//         cell count c bounds every patch's grid per direction, the largest
//         c that fits); the chord they then have enters measurement_error.
//         Grids are kept as made while their total fits the cap; past it
//         they are made again under the cap (repeated evaluation), and no
//         more than the cap's worth of grids is held at any time.
// Threads Samples are measured side by side (core/parallel.h), each into its
//         own slot, with per-thread B-rep copies; sums run in sample order,
//         so the figures do not depend on the thread count.
#pragma once

#include "stripweave/core/stopwatch.h"
#include "stripweave/surface/surface.h"
#include "stripweave/surfacing/bspline.h"

namespace stripweave {

struct DeviationOptions {
  double spacing = 0;        // model units; 0: the solver mesh's mean edge length
  double chord = 0;          // model units; 0: tolerance / 10
  int samples_per_span = 8;
  Index max_source_samples = 600000;  // the spacing grows to stay under this
  // The patch tessellation's triangles at most. With its AABB tree it takes
  // about 105 bytes a triangle (measured: halving a 1.2M cap lowered the
  // refit's peak by 62 MB), so 600K keeps it near 63 MB, within the main
  // job's 400 MB on a 30K-triangle part (issue 22: a 618-face assembly's job
  // peaked at 437 MB with a 1.2M cap, 379 MB with this one). Patches whose
  // chord would need more cells than their share get coarser grids, the
  // finest-needing first: the cap binds on networks with rippling patches
  // far off the source, and measurement_error grows with the chord they
  // then have, so the bound stays honest (that assembly: max deviation and
  // coverage the same to 5 digits, the bound 3.4 -> 6.6 model units).
  Index max_patch_triangles = 600000;
};

struct PatchDeviation {
  double max_source_to_patch = 0, rms_source_to_patch = 0;
  double max_patch_to_source = 0, rms_patch_to_source = 0;
  Index source_samples = 0, patch_samples = 0;
  double source_area = 0;     // of the source samples that belong to it
  double max_deviation() const { return std::max(max_source_to_patch, max_patch_to_source); }
};

struct FitDeviation {
  double max_source_to_patches = 0, rms_source_to_patches = 0;
  double max_patches_to_source = 0, rms_patches_to_source = 0;
  double source_area = 0, uncovered_area = 0, coverage = 0;
  std::vector<PatchDeviation> per_patch;
  std::vector<double> triangle_uncovered;  // per solver triangle, in [0, 1]
  Index source_samples = 0, patch_samples = 0;
  Index unmeshed_faces = 0;
  double spacing = 0, measurement_error = 0;
  double source_chord = 0, patch_chord = 0;  // largest centroid chordal errors of the two tessellations
  Index patch_triangles = 0;                 // of the patch tessellation (within max_patch_triangles)
  StageTimings timings;                      // ms per step
};

FitDeviation fit_deviation(const Surface& surface, const std::vector<BSplinePatch>& patches, double tolerance,
                           const DeviationOptions& options = {});

// The patches -> source direction alone, exactly as fit_deviation measures
// it (per patch max_patch_to_source, rms_patch_to_source, patch_samples; the
// overall max and RMS; the source side left zero): enough to judge a trial
// fit by each patch's own distance, without the patch tessellation, its tree
// and a query per source sample (half the measurement's time).
FitDeviation patches_to_source_deviation(const Surface& surface, const std::vector<BSplinePatch>& patches,
                                         double tolerance, const DeviationOptions& options = {});

// Adds the source -> patches side (and the coverage) to what
// patches_to_source_deviation measured of the same patches: together exactly
// fit_deviation's figures, the patches -> source side not measured again.
// The source samples are made again (sample_source: 0.1 to 0.3 s on the
// corpus's B-reps, under 1 % of a refit); keeping them between the two calls
// would keep the source tessellation alive through the trial fits that run
// between a trial's measure and its completion (complete_deviation).
void add_source_side(const Surface& surface, const std::vector<BSplinePatch>& patches, double tolerance,
                     const DeviationOptions& options, FitDeviation& partial);

}  // namespace stripweave
