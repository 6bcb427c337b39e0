#include "stripweave/surfacing/source_projection.h"

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/occt/brep_source.h"

#include <algorithm>
#include <limits>

namespace stripweave {

SourceProjector::SourceProjector(const Surface& surface, double edge_snap) : edge_snap_(edge_snap) {
  if (surface.brep) {
    brep_ = surface.brep.get();
    face_edges_.resize(brep_->num_faces());
    face_edges_known_.assign(brep_->num_faces(), false);
  } else if (surface.source_mesh && surface.source_mesh->num_triangles() > 0) {
    locator_ = std::make_unique<SurfaceLocator>(*surface.source_mesh);
  }
}

SourceProjector::~SourceProjector() = default;

Vec3 SourceProjector::fallback(const Vec3& p) const { return locator_ ? locator_->closest(p).point : p; }

Vec3 SourceProjector::on_faces(const std::vector<Index>& faces, const Vec3& p) const {
  if (!brep_) return fallback(p);
  Vec3 best = p;
  double best_d = std::numeric_limits<double>::infinity();
  for (Index f : faces) {
    if (f < 0 || f >= brep_->num_faces()) continue;
    double d;
    const Vec3 q = brep_->project_to_face(f, p, &d, edge_snap_);
    if (d < best_d) best_d = d, best = q;
  }
  return best;
}

Vec3 SourceProjector::on_sharp(const std::vector<Index>& faces, const Vec3& p) const {
  if (!brep_) return fallback(p);
  std::vector<Index> edges;
  for (Index f : faces) {
    if (f < 0 || f >= brep_->num_faces()) continue;
    if (!face_edges_known_[f]) face_edges_[f] = brep_->face_edges(f), face_edges_known_[f] = true;
    edges.insert(edges.end(), face_edges_[f].begin(), face_edges_[f].end());
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  Vec3 best = p;
  double best_d = std::numeric_limits<double>::infinity();
  for (Index e : edges) {
    double d;
    const Vec3 q = brep_->project_to_edge(e, p, &d);
    if (d < best_d) best_d = d, best = q;
  }
  return best_d <= edge_snap_ ? best : on_faces(faces, p);
}

}  // namespace stripweave
