// SourceProjector: puts sample points of the layout back onto the exact
// source the refit approximates.
//
// Input   the Surface (its source B-rep `brep`, else its full-resolution
//         `source_mesh`, else nothing), the snap distance for sharp edges
//         (model units).
// Output  projected points, model units.
// Method  The layout's polylines and patch meshes live on the solver mesh,
//         a chordal approximation of the source. Each sample knows the
//         B-rep faces it may lie on (the source_face of the patch triangles
//         around it), so
//           on_faces(F, p)  one face: the nearest point of its surface
//                           (BrepSource::project_to_face, untrimmed: a
//                           sample near a face border stays on the smooth
//                           continuation of its own face); several (a
//                           sample by a face border): the nearest foot
//                           point within its face's trim, else the nearest
//                           point of the faces' edges (never a face's
//                           continuation past a crease, off the part);
//           on_sharp(F, p)  the nearest point of the B-rep edges bounding
//                           the faces F when one is within the snap distance
//                           (a sharp layout edge runs along a B-rep edge),
//                           else on_faces;
//           normal_on_faces(F, p)  the exact outward normal there
//                           (BrepSource::evaluate);
//         without a B-rep, the nearest point of the source mesh (CGAL AABB
//         tree, SurfaceLocator) or p itself.
// Not thread-safe (BrepSource caches per-face analysers): a thread takes a
// thread_copy().
#pragma once

#include "stripweave/surface/surface.h"

#include <memory>

namespace stripweave {

class SurfaceLocator;

class SourceProjector {
 public:
  SourceProjector(const Surface& surface, double edge_snap);
  // For another thread: the B-rep through a thread copy of its own
  // (BrepSource::thread_copy); null when the source is not a B-rep.
  std::unique_ptr<SourceProjector> thread_copy() const;
  // Forget the previous foot points (BrepSource::forget_warm_starts).
  void forget_warm_starts() const;
  ~SourceProjector();

  bool exact() const { return brep_ != nullptr; }
  Vec3 on_faces(const std::vector<Index>& faces, const Vec3& p) const;
  Vec3 on_sharp(const std::vector<Index>& faces, const Vec3& p) const;
  // The outward unit normal of the nearest of the faces at p (zero without
  // a B-rep, or where no face has one).
  Vec3 normal_on_faces(const std::vector<Index>& faces, const Vec3& p) const;

 private:
  Vec3 fallback(const Vec3& p) const;
  // Per B-rep face or edge, its bounding box (from the geometry), when first asked for.
  struct LazyBoxes {
    std::vector<BoundingBox> box;
    std::vector<bool> known;
  };
  // A lower bound of the distance from p to face or edge i (`of` names the box).
  double box_distance(LazyBoxes& boxes, Index i, const Vec3& p, BoundingBox (BrepSource::*of)(Index) const) const;
  Vec3 nearest_on_edges(const std::vector<Index>& faces, const Vec3& p, double* distance) const;
  SourceProjector() = default;
  void use_brep(const BrepSource* brep);  // and size its per-face caches
  const BrepSource* brep_ = nullptr;
  std::shared_ptr<const BrepSource> own_brep_;  // a thread copy's
  std::unique_ptr<SurfaceLocator> locator_;
  double edge_snap_ = 0;
  mutable std::vector<std::vector<Index>> face_edges_;  // per B-rep face, lazily: sorted, distinct
  mutable std::vector<bool> face_edges_known_;
  mutable LazyBoxes face_boxes_, edge_boxes_;
};

}  // namespace stripweave
