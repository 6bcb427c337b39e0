// BrepSource: a B-rep shape and the exact geometry queries the pipeline needs
// (the OpenCASCADE adapter; no OCCT type crosses this header).
//
// Construction
//   from_file(path)          STEP (.step/.stp), IGES (.iges/.igs) or BREP
//                            (.brep/.brp), by extension
//   from_brep_string(text)   as FreeCAD's Shape.exportBrepToString() gives it
//   Both throw InputError for an unreadable file, a shape with no faces, or a
//   non-manifold shape (an edge shared by more than two faces). Loose faces
//   (free edges that coincide) are sewn into shells first, with a warning
//   (occt/sew_loose_faces.h): face and edge ids are the sewn shape's.
//   warnings()  the repairs made on reading, one line each
//
// Queries (face and edge ids index OCCT's TopExp face/edge maps, 0-based)
//   tessellate(deflection, angle)  BRepMesh_IncrementalMesh, then the per-face
//       triangulations welded into one mesh along shared edges (seams,
//       degenerate edges and vertices shared by many faces included), with
//       the source face of every triangle and the mesh edges lying on each
//       B-rep edge.
//   sharp_edges(angle)  per B-rep edge: the largest angle between the two
//       faces' outward normals along the edge exceeds `angle` (tangent
//       continuous edges such as fillet borders are not sharp)
//   edge_face_count(e)  1 for a free (open boundary) edge, 2 otherwise; a
//       seam, bounded by one face on both sides, counts 2
//   evaluate(face, p)   the point of the face's surface nearest to p, with
//       its outward normal, principal curvatures (positive where convex) and
//       directions, accounting for reversed faces
//   project_to_edge(e, p)  the point of edge e's curve nearest to p
//   project_to_face(f, p)  the point of the face's (untrimmed) surface
//       nearest to p, position only: evaluate() without the normal and
//       curvature, for bulk sampling (the surfacing stage's refit); with
//       near > 0 the search starts from the face's previous answer (a local
//       Newton kept within the surface's parameter bounds, settling on the
//       border where the foot point lies beyond it) and falls back to the
//       global one only when that does not settle or lands farther than
//       `near` from p: many times faster on B-spline faces for samples that
//       come in spatial order and lie close to the surface (OCCT's
//       NextValueOfUV searched globally whenever a step left the bounds:
//       every sample by a face border projected onto its neighbour, about
//       half the refit's sampling time); with near = 0 (no previous answer
//       to start from) the search starts at the face's start-grid sample
//       nearest p (a grid over the face's (u, v) box, its normals turning
//       15 degrees at most between neighbours) and falls back to the global
//       one only when that does not settle; near < 0: the global search
//       alone (OCCT's ShapeAnalysis_Surface, the reference for tests);
//       with `inside`, whether that
//       point lies within the face's trim (BRepTopAdaptor_FClass2d, cached
//       per face; on the border counts as inside)
//   dense_samples(spacing, chord)  the faces as a fine triangle mesh whose
//       vertices lie exactly on their face's surface, and one exact sample
//       per triangle with its area, for measuring a fit (brep_dense_samples.cpp)
//   foot_on_face(f, p, uv)  the point of face f nearest to p by a local
//       Newton from uv (a point within the trim; kept within the face's
//       (u, v) box), or where that lands past the trim, the nearest of the
//       start and the face's edges: the exact refinement of a nearest point
//       found on the fine mesh
#pragma once

#include "stripweave/surface/triangle_mesh.h"

#include <memory>
#include <string>
#include <vector>

namespace stripweave {

struct SurfacePoint {
  Vec3 position = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
  double k_min = 0, k_max = 0;
  Vec3 d_min = Vec3::Zero(), d_max = Vec3::Zero();
  bool normal_defined = false;
  bool curvature_defined = false;
  double distance = 0;  // from the query point to `position`
};

struct BrepTessellation {
  TriangleMesh mesh;                     // welded, model units, outward oriented
  std::vector<Index> face_of_triangle;   // per triangle
  std::vector<EdgeKey> edge_segments;    // mesh edges lying on B-rep edges
  std::vector<Index> segment_edge;       // per segment: its B-rep edge
  std::vector<Index> corner_vertices;    // mesh vertices at B-rep vertices
  Index unmeshed_faces = 0;              // faces BRepMesh gave no triangles
  Index collapsed_triangles = 0;         // dropped at poles / degenerate edges
};

// The source B-rep densely sampled (model units): every face's BRepMesh
// triangles subdivided in their (u, v) until no sub-triangle is longer than
// `spacing` (the samples, at those sub-triangles' centroids), and further
// until none deviates from the surface by more than `chord` at its centroid
// (the mesh); every point evaluated exactly on its face's surface at its
// (u, v). Faces are not welded to each other (distances need no topology).
struct BrepDenseSamples {
  TriangleMesh mesh;                 // vertices exactly on the source
  std::vector<Vec2> uv;              // per mesh vertex, its face's (u, v)
  std::vector<Index> face;           // per mesh triangle, its B-rep face
  std::vector<Vec3> points;          // the samples, exactly on the source
  std::vector<double> area;          // per sample, its weight
  double max_chord = 0;              // largest centroid deviation of a triangle from its surface point
  Index unmeshed_faces = 0;          // faces BRepMesh gave no triangles (no samples)
  double unmeshed_area = 0;          // their area (BRepGProp)
};

class BrepSource {
 public:
  static std::shared_ptr<BrepSource> from_file(const std::string& path);
  static std::shared_ptr<BrepSource> from_brep_string(const std::string& text);
  ~BrepSource();

  const std::vector<std::string>& warnings() const;
  Index num_faces() const;
  Index num_edges() const;
  BoundingBox bounding_box() const;
  BoundingBox face_bounding_box(Index face) const;  // from its geometry (conservative)
  BoundingBox edge_bounding_box(Index edge) const;  // likewise

  BrepTessellation tessellate(double linear_deflection, double angular_deflection_rad) const;
  std::vector<bool> sharp_edges(double angle_deg) const;
  Index edge_face_count(Index edge) const;
  // B-rep edges bounding a face.
  std::vector<Index> face_edges(Index face) const;

  SurfacePoint evaluate(Index face, const Vec3& p) const;
  Vec3 project_to_edge(Index edge, const Vec3& p, double* distance = nullptr) const;
  Vec3 project_to_face(Index face, const Vec3& p, double* distance = nullptr, double near = 0,
                       bool* inside = nullptr) const;

  BrepDenseSamples dense_samples(double spacing, double chord) const;
  // On return uv is the foot point's (u, v); *distance its distance from p.
  Vec3 foot_on_face(Index face, const Vec3& p, Vec2& uv, double* distance = nullptr) const;

  // The shape as a BREP string (for the refit stage and for FreeCAD).
  std::string to_brep_string() const;

  // The same shape (same face and edge numbering) with caches of its own:
  // project_to_face keeps per-face analysers and its previous answer, so
  // one BrepSource must not be used by two threads; each thread takes a
  // copy. forget_warm_starts() drops the previous answers, so that what
  // follows does not depend on what was projected before (on which thread).
  std::shared_ptr<BrepSource> thread_copy() const;
  void forget_warm_starts() const;
  // Drops the per-face analysers, classifiers and adaptors (rebuilt lazily
  // when asked again): a stage that is done with the faces gives their
  // memory back (an assembly of many B-spline faces: 300 MB of analysers
  // after loading, which stayed under every later peak).
  void release_caches() const;
  // How many per-face analysers hold OCCT's global-search grid now (at most a bound:
  // brep_source_impl.h's kSearchGrids).
  Index held_search_grids() const;

  struct Impl;

 private:
  explicit BrepSource(std::unique_ptr<Impl> impl);
  static std::shared_ptr<BrepSource> checked(std::unique_ptr<Impl> impl, const std::string& what);
  std::unique_ptr<Impl> impl_;
};

// True if the extension names a B-rep format BrepSource::from_file reads.
bool is_brep_file(const std::string& path);

}  // namespace stripweave
