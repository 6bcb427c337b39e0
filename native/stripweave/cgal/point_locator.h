// PointLocator: the nearest of a set of points (CGAL kd-tree adapter).
//
// Built once per set (O(n log n)); answers in O(log n) on average. The B-rep
// source uses it to start a local foot-point search from the sample of a
// face's start grid nearest the query (occt/brep_source.cpp), where OCCT's
// global search would sample a grid of the whole surface per query.
//   PointLocator(points)  any units
//   nearest(p) -> the index of the point nearest p (kInvalid when empty)
//   empty()    -> no point
#pragma once

#include "stripweave/core/types.h"

#include <memory>
#include <vector>

namespace stripweave {

class PointLocator {
 public:
  explicit PointLocator(const std::vector<Vec3>& points);
  ~PointLocator();
  Index nearest(const Vec3& p) const;
  bool empty() const { return empty_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool empty_ = true;
};

}  // namespace stripweave
