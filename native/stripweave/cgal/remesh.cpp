// Isotropic remeshing through CGAL Polygon_mesh_processing.
//
// The input goes into a CGAL::Surface_mesh carrying four properties that the
// remesher maintains for us as it splits, collapses and flips:
//   face  patch id        (face_patch_map: new faces inherit their patch)
//   edge  constrained     (edge_is_constrained_map: halves of a split
//                          constrained edge stay constrained)
//   vertex fixed          (vertex_is_constrained_map: never moved nor removed)
//   vertex source id      (ours, untouched by CGAL: vertices created by a
//                          split start from the property's default, kInvalid)
// and comes back as a densely indexed TriangleMesh.
#include "stripweave/cgal/remesh.h"

#include "stripweave/core/error.h"

#include "stripweave/cgal/surface_mesh_adapter.h"

#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace stripweave {
namespace {

using namespace cgal_mesh;

// Vertex point map that ignores writes to fixed vertices. CGAL 5.5's
// isotropic_remeshing honours vertex_is_constrained_map when collapsing and
// projecting, but its tangential relaxation step does not consult it, so a
// fixed vertex away from constrained edges drifts (CGAL issue #8388, fixed in
// CGAL 6). Every position the remesher writes goes through put(), so refusing
// it here keeps the fixed vertices exactly in place on any CGAL version.
struct FixedAwarePointMap {
  using key_type = VertexId;
  using value_type = Kernel::Point_3;
  using reference = const Kernel::Point_3&;
  using category = boost::read_write_property_map_tag;

  Mesh::Property_map<VertexId, Kernel::Point_3> points;
  Mesh::Property_map<VertexId, bool> fixed;

  friend reference get(const FixedAwarePointMap& m, VertexId v) { return m.points[v]; }
  friend void put(const FixedAwarePointMap& m, VertexId v, const Kernel::Point_3& p) {
    if (!m.fixed[v]) m.points[v] = p;
  }
};

}  // namespace

RemeshResult remesh_isotropic(const TriangleMesh& mesh, const std::vector<Index>& patch_of_triangle,
                              const std::vector<EdgeKey>& constrained_edges,
                              const std::vector<Index>& constrained_vertices, double target_edge_length,
                              int iterations) {
  const Index nv = mesh.num_vertices();
  const Index nt = mesh.num_triangles();
  if (static_cast<Index>(patch_of_triangle.size()) != nt) {
    throw std::invalid_argument("remesh_isotropic: patch_of_triangle has " + std::to_string(patch_of_triangle.size()) +
                                " entries for " + std::to_string(nt) + " triangles");
  }
  if (!(target_edge_length > 0.0) || !std::isfinite(target_edge_length)) {
    throw std::invalid_argument("remesh_isotropic: target edge length must be positive, got " +
                                std::to_string(target_edge_length));
  }
  for (Index v : constrained_vertices) {
    if (v < 0 || v >= nv) {
      throw std::invalid_argument("remesh_isotropic: constrained vertex " + std::to_string(v) + " does not exist");
    }
  }

  Mesh sm;
  auto source = fill_surface_mesh(sm, mesh, "remesh");
  auto fixed = sm.add_property_map<VertexId, bool>("v:stripweave_fixed", false).first;
  auto constrained = sm.add_property_map<EdgeId, bool>("e:stripweave_constrained", false).first;
  auto patch = sm.add_property_map<FaceId, Index>("f:stripweave_patch", 0).first;
  for (Index t = 0; t < nt; ++t) patch[FaceId(t)] = patch_of_triangle[t];  // face t is Face_index(t)

  for (const EdgeKey& e : constrained_edges) {
    const auto [h, found] =
        (e[0] >= 0 && e[0] < nv && e[1] >= 0 && e[1] < nv)
            ? CGAL::halfedge(VertexId(e[0]), VertexId(e[1]), sm)
            : std::make_pair(Mesh::null_halfedge(), false);
    if (!found) {
      throw std::invalid_argument("remesh_isotropic: constrained edge (" + std::to_string(e[0]) + ", " +
                                  std::to_string(e[1]) + ") is not an edge of the mesh");
    }
    constrained[sm.edge(h)] = true;
  }
  // CGAL keeps patch borders and mesh boundaries on its own, but only edges
  // in the map report their status back to us after splits.
  for (EdgeId e : sm.edges()) {
    const auto h = sm.halfedge(e), o = sm.opposite(h);
    if (sm.is_border(h) || sm.is_border(o) || patch[sm.face(h)] != patch[sm.face(o)]) constrained[e] = true;
  }
  for (Index v : constrained_vertices) fixed[VertexId(v)] = true;

  namespace PMP = CGAL::Polygon_mesh_processing;
  PMP::isotropic_remeshing(faces(sm), target_edge_length, sm,
                           CGAL::parameters::number_of_iterations(static_cast<unsigned>(std::max(iterations, 0)))
                               .vertex_point_map(FixedAwarePointMap{sm.points(), fixed})
                               .face_patch_map(patch)
                               .edge_is_constrained_map(constrained)
                               .vertex_is_constrained_map(fixed)
                               // Long constrained edges must be split to reach the
                               // target size; their vertices stay on the polyline.
                               .protect_constraints(false)
                               .relax_constraints(false));

  // Compact the removed elements away; properties are compacted along, and
  // the surviving indices become 0..n-1.
  sm.collect_garbage();

  RemeshResult out;
  out.mesh = mesh_of(sm);
  out.source_vertex.reserve(sm.number_of_vertices());
  std::vector<Index> output_of_input(nv, kInvalid);
  for (VertexId v : sm.vertices()) {
    out.source_vertex.push_back(source[v]);
    if (source[v] != kInvalid) output_of_input[source[v]] = static_cast<Index>(v.idx());
  }
  out.patch_of_triangle.reserve(sm.number_of_faces());
  for (FaceId f : sm.faces()) out.patch_of_triangle.push_back(patch[f]);
  for (EdgeId e : sm.edges()) {
    const auto h = sm.halfedge(e), o = sm.opposite(h);
    const bool border = sm.is_border(h) || sm.is_border(o) || patch[sm.face(h)] != patch[sm.face(o)];
    if (constrained[e] || border) {
      out.constrained_edges.push_back(edge_key(static_cast<Index>(sm.source(h).idx()), static_cast<Index>(sm.target(h).idx())));
    }
  }
  out.constrained_vertices.reserve(constrained_vertices.size());
  for (Index v : constrained_vertices) {
    // A fixed vertex is never collapsed, so it is always found.
    out.constrained_vertices.push_back(output_of_input[v]);
  }
  return out;
}

}  // namespace stripweave
