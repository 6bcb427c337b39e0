// Building the Surface from a B-rep or a mesh (the first pipeline stage).
//
// B-rep:  tessellate (BRepMesh) -> weld faces along shared edges -> classify
//         B-rep edges (sharp / boundary / smooth) -> isotropic remesh to the
//         target size with every B-rep edge kept as a constrained polyline ->
//         project vertices back onto their faces (edges, corners) and take
//         exact normals and curvature there.
// Mesh:   sanitize (repairs with warnings, or an InputError) -> sharp edges
//         by dihedral angle, chained, short spurious chains dropped ->
//         (an input over 8 times the target: its short edges collapsed,
//         features and boundaries kept) -> isotropic remesh with features
//         and boundaries constrained -> (after a collapse: the proxy's
//         vertices projected onto the original, paper §8.1) ->
//         curvature by jet fitting over a neighbourhood scaled to the model.
// Both end normalized to bounding-box diagonal 1 (paper §8).
#pragma once

#include "stripweave/core/progress.h"
#include "stripweave/surface/surface.h"

namespace stripweave {

// The solver mesh's size limit: a larger target, or a larger mesh kept with
// target 0, is refused (time and memory of every later stage grow with it).
constexpr Index kMaxSolverTriangles = 1000000;

// Every option is checked on entry (InputError naming it and its value).
struct SurfaceOptions {
  // B-rep tessellation: chordal deflection in model units; 0 means
  // relative_deflection times the bounding-box diagonal.
  double deflection = 0.0;
  double relative_deflection = 1e-3;
  double angular_deflection_deg = 20.0;
  // Size of the solver mesh; 0 keeps the tessellation or input mesh as is.
  Index target_triangles = 30000;
  // Edges whose faces meet at more than this angle are sharp features.
  double feature_angle_deg = 30.0;
  // Mesh input: isolated feature chains shorter than this (fraction of the
  // diagonal) are noise and dropped.
  double min_feature_length = 0.02;
  // Mesh input: jet-fitting radius as a fraction of the diagonal; 0 picks
  // max(0.015, 2 mean edge lengths): scaled to the model, so scan noise does
  // not swamp the directions, yet never fewer than about two rings.
  double curvature_radius = 0.0;
  int remesh_iterations = 3;
};

class BrepSource;

Surface surface_from_brep(std::shared_ptr<const BrepSource> brep, const SurfaceOptions& options,
                          Progress* progress = nullptr);
Surface surface_from_mesh(const TriangleMesh& raw, const SurfaceOptions& options, Progress* progress = nullptr);

// By extension: B-rep formats (STEP, IGES, BREP) or mesh formats (STL, OBJ,
// OFF, PLY). Throws InputError for anything else.
Surface load_surface(const std::string& path, const SurfaceOptions& options, Progress* progress = nullptr);

}  // namespace stripweave
