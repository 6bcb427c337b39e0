// Surface: the first stage's output, the input of every later stage.
//
// A welded, oriented manifold triangle mesh at the solver's density, in
// normalized units (bounding-box diagonal 1, paper §8), carrying
//   per vertex    normal, principal curvatures k_min <= k_max (positive where
//                 convex, in 1/normalized length) and unit principal
//                 directions d_min, d_max (paper §5.5); exact from the B-rep
//                 where there is one, estimated by jet fitting on meshes
//   per triangle  the source B-rep face (kInvalid for meshes)
//   per edge      its class: regular, sharp feature (§5.6) or open boundary
//                 (§5.7), and the id of its feature curve
//   feature curves  chains of mesh edges, each with an id (its index)
//   boundary loops  closed vertex chains along the open boundary
// and the similarity back to model units. The source B-rep (if any) is kept
// for later projection and refitting.
#pragma once

#include "stripweave/core/stopwatch.h"
#include "stripweave/surface/mesh_topology.h"
#include "stripweave/surface/triangle_mesh.h"

#include <memory>
#include <string>

namespace stripweave {

class BrepSource;

enum class EdgeClass : std::uint8_t { Regular = 0, Feature = 1, Boundary = 2 };

// A chain of mesh edges: consecutive vertices are joined by mesh edges. A
// closed curve does not repeat its first vertex.
struct FeatureCurve {
  std::vector<Index> vertices;
  bool closed = false;
};

// model point = center + scale * normalized point
struct Similarity {
  Vec3 center = Vec3::Zero();
  double scale = 1.0;
  Vec3 to_model(const Vec3& p) const { return center + scale * p; }
  Vec3 to_normalized(const Vec3& p) const { return (p - center) / scale; }
};

struct Surface {
  TriangleMesh mesh;  // normalized units
  MeshTopology topology;
  Similarity similarity;

  std::vector<Vec3> normal;  // per vertex, unit, outward
  std::vector<double> k_min, k_max;
  std::vector<Vec3> d_min, d_max;

  std::vector<Index> source_face;     // per triangle
  std::vector<EdgeClass> edge_class;  // per edge
  std::vector<Index> edge_curve;      // per edge: feature curve id or kInvalid
  std::vector<FeatureCurve> feature_curves;
  std::vector<std::vector<Index>> boundary_loops;

  Index components = 0;
  int genus = 0;  // summed over components
  Index brep_faces = 0;
  std::vector<std::string> warnings;
  StageTimings timings;  // how long each stage of building took
  Index input_triangles = 0;  // of the tessellation or input mesh, before remeshing

  std::shared_ptr<const BrepSource> brep;           // the source B-rep, or null
  std::shared_ptr<const TriangleMesh> source_mesh;  // the full-resolution input mesh (model units), or null

  Index feature_edge_count() const {
    Index n = 0;
    for (EdgeClass c : edge_class) n += c == EdgeClass::Feature;
    return n;
  }
};

}  // namespace stripweave
