#include "stripweave/cgal/segment_locator.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <limits>

namespace stripweave {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Primitive = CGAL::AABB_segment_primitive<Kernel, std::vector<Segment>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point to_point(const Vec3& p) { return Point(p.x(), p.y(), p.z()); }
}  // namespace

struct SegmentLocator::Impl {
  std::vector<Segment> segments;  // the tree refers to them: they live as long as it
  Tree tree;
};

SegmentLocator::SegmentLocator(const std::vector<Segment3>& segments) : impl_(std::make_unique<Impl>()) {
  for (const Segment3& s : segments)
    if (s[0] != s[1]) impl_->segments.emplace_back(to_point(s[0]), to_point(s[1]));
  empty_ = impl_->segments.empty();
  if (empty_) return;
  impl_->tree.insert(impl_->segments.cbegin(), impl_->segments.cend());
  impl_->tree.accelerate_distance_queries();
}

SegmentLocator::~SegmentLocator() = default;

double SegmentLocator::distance(const Vec3& p) const {
  if (empty_) return std::numeric_limits<double>::infinity();
  return std::sqrt(CGAL::to_double(impl_->tree.squared_distance(to_point(p))));
}

}  // namespace stripweave
