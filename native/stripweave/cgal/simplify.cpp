#include "stripweave/cgal/simplify.h"

#include "stripweave/cgal/surface_mesh_adapter.h"

#include <CGAL/Surface_mesh_simplification/Edge_collapse_visitor_base.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_filter.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Edge_length_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Edge_length_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Midpoint_placement.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <string>

namespace stripweave {
namespace {

using namespace cgal_mesh;
namespace SMS = CGAL::Surface_mesh_simplification;

// Midpoints, except where a vertex is fixed: there the fixed point (both
// fixed: no collapse).
struct FixedAwarePlacement {
  Mesh::Property_map<VertexId, bool> fixed;
  template <typename Profile>
  boost::optional<typename Profile::Point> operator()(const Profile& p) const {
    const bool f0 = fixed[p.v0()], f1 = fixed[p.v1()];
    if (f0 && f1) return boost::none;
    if (f0) return p.p0();
    if (f1) return p.p1();
    return SMS::Midpoint_placement<Mesh>()(p);
  }
};

// The surviving vertex of a collapse inherits a fixed vertex's flag and id.
struct KeepFixed : SMS::Edge_collapse_visitor_base<Mesh> {
  Mesh::Property_map<VertexId, bool> fixed;
  Mesh::Property_map<VertexId, Index> source;
  Index pending_source = kInvalid;
  template <typename Profile>
  void OnCollapsing(const Profile& p, const boost::optional<typename Profile::Point>&) {
    pending_source = fixed[p.v0()] ? source[p.v0()] : fixed[p.v1()] ? source[p.v1()] : kInvalid;
  }
  template <typename Profile>
  void OnCollapsed(const Profile&, VertexId kept) {
    if (pending_source == kInvalid) return;
    fixed[kept] = true;
    source[kept] = pending_source;
  }
};

}  // namespace

SimplifyResult simplify_short_edges(const TriangleMesh& mesh, const std::vector<EdgeKey>& constrained_edges,
                                    const std::vector<Index>& constrained_vertices, double min_edge) {
  const Index nv = mesh.num_vertices();
  Mesh sm;
  auto source = fill_surface_mesh(sm, mesh, "simplify");
  auto fixed = sm.add_property_map<VertexId, bool>("v:stripweave_fixed", false).first;
  auto constrained = sm.add_property_map<EdgeId, bool>("e:stripweave_constrained", false).first;
  for (const EdgeKey& e : constrained_edges) {
    const auto [h, found] = CGAL::halfedge(VertexId(e[0]), VertexId(e[1]), sm);
    if (!found) continue;
    constrained[sm.edge(h)] = true;
  }
  for (EdgeId e : sm.edges())
    if (sm.is_border(e)) constrained[e] = true;
  for (EdgeId e : sm.edges())
    if (constrained[e]) fixed[sm.vertex(e, 0)] = fixed[sm.vertex(e, 1)] = true;
  for (Index v : constrained_vertices) fixed[VertexId(v)] = true;

  KeepFixed visitor;
  visitor.fixed = fixed;
  visitor.source = source;
  SMS::Edge_length_stop_predicate<double> stop(min_edge);
  SMS::edge_collapse(sm, stop,
                     CGAL::parameters::edge_is_constrained_map(constrained)
                         .get_cost(SMS::Edge_length_cost<Mesh>())
                         .get_placement(FixedAwarePlacement{fixed})
                         .filter(SMS::Bounded_normal_change_filter<>())
                         .visitor(visitor));
  sm.collect_garbage();

  SimplifyResult out;
  out.mesh = mesh_of(sm);
  std::vector<Index> output_of_input(nv, kInvalid);
  for (VertexId v : sm.vertices())
    if (fixed[v] && source[v] != kInvalid) output_of_input[source[v]] = static_cast<Index>(v.idx());
  for (EdgeId e : sm.edges())
    if (constrained[e] || sm.is_border(e))
      out.constrained_edges.push_back(
          edge_key(static_cast<Index>(sm.vertex(e, 0).idx()), static_cast<Index>(sm.vertex(e, 1).idx())));
  for (Index v : constrained_vertices)
    if (output_of_input[v] != kInvalid) out.constrained_vertices.push_back(output_of_input[v]);
  return out;
}

}  // namespace stripweave
