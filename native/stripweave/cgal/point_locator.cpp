#include "stripweave/cgal/point_locator.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

namespace stripweave {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
// The tree holds indices; their coordinates come from the points vector.
using PointMap = CGAL::Pointer_property_map<Point>::type;
using Traits = CGAL::Search_traits_adapter<std::size_t, PointMap, CGAL::Search_traits_3<Kernel>>;
using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
using Tree = Search::Tree;
}  // namespace

struct PointLocator::Impl {
  std::vector<Point> points;
  std::unique_ptr<Tree> tree;
};

PointLocator::PointLocator(const std::vector<Vec3>& points) : impl_(std::make_unique<Impl>()) {
  impl_->points.reserve(points.size());
  for (const Vec3& p : points) impl_->points.emplace_back(p.x(), p.y(), p.z());
  empty_ = points.empty();
  if (empty_) return;
  std::vector<std::size_t> index(points.size());
  for (std::size_t i = 0; i < index.size(); ++i) index[i] = i;
  const PointMap map = CGAL::make_property_map(impl_->points);
  impl_->tree = std::make_unique<Tree>(index.begin(), index.end(), Tree::Splitter(), Traits(map));
  impl_->tree->build();  // now, not lazily on the first (possibly concurrent) query
}

PointLocator::~PointLocator() = default;

Index PointLocator::nearest(const Vec3& p) const {
  if (empty_) return kInvalid;
  const Traits traits(CGAL::make_property_map(impl_->points));
  Search search(*impl_->tree, Point(p.x(), p.y(), p.z()), 1, 0, true,
                Search::Distance(traits.point_property_map()));
  return static_cast<Index>(search.begin()->first);
}

}  // namespace stripweave
