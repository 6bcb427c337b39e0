#include "stripweave/surfacing/source_projection.h"

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/occt/brep_source.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace stripweave {

SourceProjector::SourceProjector(const Surface& surface, double edge_snap) : edge_snap_(edge_snap) {
  if (surface.brep) {
    use_brep(surface.brep.get());
  } else if (surface.source_mesh && surface.source_mesh->num_triangles() > 0) {
    locator_ = std::make_unique<SurfaceLocator>(*surface.source_mesh);
  }
}

SourceProjector::~SourceProjector() = default;

std::unique_ptr<SourceProjector> SourceProjector::thread_copy() const {
  if (!brep_) return nullptr;
  std::unique_ptr<SourceProjector> copy(new SourceProjector());
  copy->own_brep_ = brep_->thread_copy();
  copy->use_brep(copy->own_brep_.get());
  copy->edge_snap_ = edge_snap_;
  return copy;
}

void SourceProjector::use_brep(const BrepSource* brep) {
  brep_ = brep;
  face_edges_.assign(brep->num_faces(), {});
  face_edges_known_.assign(brep->num_faces(), false);
  face_boxes_ = {std::vector<BoundingBox>(brep->num_faces()), std::vector<bool>(brep->num_faces(), false)};
  edge_boxes_ = {std::vector<BoundingBox>(brep->num_edges()), std::vector<bool>(brep->num_edges(), false)};
}

void SourceProjector::forget_warm_starts() const {
  if (brep_) brep_->forget_warm_starts();
}

Vec3 SourceProjector::fallback(const Vec3& p) const { return locator_ ? locator_->closest(p).point : p; }

Vec3 SourceProjector::on_faces(const std::vector<Index>& faces, const Vec3& p) const {
  if (!brep_) return fallback(p);
  Vec3 best = p, best_inside = p;
  double best_d = std::numeric_limits<double>::infinity(), best_inside_d = best_d;
  // One face: its untrimmed surface (the smooth continuation past the
  // border). Several (a sample by a face border): the nearest foot point
  // that lies within its face's trim; the nearest untrimmed one may lie on
  // a face's continuation beyond a crease, off the part altogether (the
  // chordal mesh cuts a convex crease, and the far face's continuation is
  // nearer than the face the point belongs to).
  const bool trimmed = faces.size() > 1;
  // Nearest face boxes first; a face whose box lies farther than the
  // nearest foot point found inside a trim cannot offer a nearer one (nor
  // can its edges): its projection, often the global search of a far
  // surface (the other side of a thin wall), is skipped.
  std::vector<std::pair<double, Index>> order;
  for (Index f : faces) {
    if (f < 0 || f >= brep_->num_faces()) continue;
    order.push_back({trimmed ? box_distance(face_boxes_, f, p, &BrepSource::face_bounding_box) : 0.0, f});
  }
  std::sort(order.begin(), order.end());
  for (const auto& [box_d, f] : order) {
    if (box_d > best_inside_d) break;
    double d;
    bool inside = true;
    const Vec3 q = brep_->project_to_face(f, p, &d, edge_snap_, trimmed ? &inside : nullptr);
    if (d < best_d) best_d = d, best = q;
    if (inside && d < best_inside_d) best_inside_d = d, best_inside = q;
  }
  if (!trimmed || best_inside_d == best_d) return best;
  // No foot point inside (the sample faces the crease itself from the
  // convex side): the nearest point of the faces' B-rep edges, if nearer
  // than any foot point inside.
  double edge_d;
  const Vec3 on_edge = nearest_on_edges(faces, p, &edge_d);
  if (edge_d < best_inside_d) return on_edge;
  return std::isfinite(best_inside_d) ? best_inside : best;
}

namespace {

// A lower bound of the distance from p to anything within the box (0 for a
// void box: nothing known, nothing skipped).
double distance_to(const BoundingBox& b, const Vec3& p) {
  if ((b.min.array() > b.max.array()).any()) return 0;
  return (b.min - p).cwiseMax(p - b.max).cwiseMax(0.0).norm();
}

}  // namespace

double SourceProjector::box_distance(LazyBoxes& boxes, Index i, const Vec3& p,
                                     BoundingBox (BrepSource::*of)(Index) const) const {
  if (!boxes.known[i]) boxes.box[i] = (brep_->*of)(i), boxes.known[i] = true;
  return distance_to(boxes.box[i], p);
}

Vec3 SourceProjector::nearest_on_edges(const std::vector<Index>& faces, const Vec3& p, double* distance) const {
  std::vector<Index> edges;
  for (Index f : faces) {
    if (f < 0 || f >= brep_->num_faces()) continue;
    std::vector<Index>& own = face_edges_[f];
    if (!face_edges_known_[f]) {
      own = brep_->face_edges(f);  // a seam edge bounds its face twice
      std::sort(own.begin(), own.end());
      own.erase(std::unique(own.begin(), own.end()), own.end());
      face_edges_known_[f] = true;
    }
    edges.insert(edges.end(), own.begin(), own.end());
  }
  std::sort(edges.begin(), edges.end());
  // Edges two of the faces share (the crease between them) first: far
  // fewer curve projections than every edge of every face.
  std::vector<Index> shared;
  for (size_t k = 1; k < edges.size(); ++k)
    if (edges[k] == edges[k - 1] && (shared.empty() || shared.back() != edges[k])) shared.push_back(edges[k]);
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  if (!shared.empty()) edges = std::move(shared);
  // Nearest edge boxes first: an edge whose box lies farther than the nearest
  // point found cannot offer a nearer one (the whole part's edges, for the
  // deviation's second look, were two thirds of a refit's time).
  std::vector<std::pair<double, Index>> order;
  order.reserve(edges.size());
  for (Index e : edges) order.push_back({box_distance(edge_boxes_, e, p, &BrepSource::edge_bounding_box), e});
  std::sort(order.begin(), order.end());
  Vec3 best = p;
  double best_d = std::numeric_limits<double>::infinity();
  for (const auto& [box_d, e] : order) {
    if (box_d > best_d) break;
    double d;
    const Vec3 q = brep_->project_to_edge(e, p, &d);
    if (d < best_d) best_d = d, best = q;
  }
  *distance = best_d;
  return best;
}

Vec3 SourceProjector::normal_on_faces(const std::vector<Index>& faces, const Vec3& p) const {
  if (!brep_) return Vec3::Zero();
  Vec3 best = Vec3::Zero();
  double best_d = std::numeric_limits<double>::infinity();
  for (Index f : faces) {
    if (f < 0 || f >= brep_->num_faces()) continue;
    const SurfacePoint sp = brep_->evaluate(f, p);
    if (sp.normal_defined && sp.distance < best_d) best_d = sp.distance, best = sp.normal;
  }
  return best;
}

Vec3 SourceProjector::on_sharp(const std::vector<Index>& faces, const Vec3& p) const {
  if (!brep_) return fallback(p);
  double d;
  const Vec3 q = nearest_on_edges(faces, p, &d);
  return d <= edge_snap_ ? q : on_faces(faces, p);
}

}  // namespace stripweave
