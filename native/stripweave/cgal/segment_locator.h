// SegmentLocator: distance from a point to the nearest of a set of segments
// (CGAL AABB tree adapter).
//
// Built once per set; answers in O(log n). The surfacing stage uses it to
// ask whether an edge of a patch mesh lies on (or by) one of the surface's
// creases (surfacing/patch_creases.h).
//   SegmentLocator(segments)  segments as pairs of end points (any units)
//   distance(p) -> the distance from p to the nearest segment, +infinity
//                  when there is none
//   empty()     -> no segment
#pragma once

#include "stripweave/surface/triangle_mesh.h"

#include <array>
#include <memory>

namespace stripweave {

using Segment3 = std::array<Vec3, 2>;

class SegmentLocator {
 public:
  explicit SegmentLocator(const std::vector<Segment3>& segments);
  ~SegmentLocator();
  double distance(const Vec3& p) const;
  bool empty() const { return empty_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool empty_ = true;
};

}  // namespace stripweave
