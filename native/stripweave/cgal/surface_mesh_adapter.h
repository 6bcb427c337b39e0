// Between our TriangleMesh and a CGAL::Surface_mesh: the common part of the
// CGAL adapters that edit a mesh (remesh.cpp, simplify.cpp). Include only from
// CGAL translation units.
//
// fill_surface_mesh(sm, mesh, work) -> the "v:stripweave_source" vertex map:
//   vertex i of `mesh` becomes Vertex_index(i) with source i (vertices the
//   editing creates keep kInvalid); face t becomes Face_index(t). InputError
//   naming `work` ("remesh", "simplify") and the triangle for a triangle the
//   halfedge structure refuses (non-manifold or inconsistently oriented).
// mesh_of(sm) -> TriangleMesh: after collect_garbage, densely indexed, each
//   face in its halfedges' (the input's counter-clockwise) order.
#pragma once

#include "stripweave/core/error.h"
#include "stripweave/surface/triangle_mesh.h"

// The kernel must agree across the library's CGAL translation units (one
// definition rule). Editing constructs points (midpoints, projections) and
// tests orientations: an exact-predicates kernel is what CGAL supports here.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <string>

namespace stripweave::cgal_mesh {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexId = Mesh::Vertex_index;
using EdgeId = Mesh::Edge_index;
using FaceId = Mesh::Face_index;

inline std::string point_text(const Vec3& p) {
  return "(" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " + std::to_string(p.z()) + ")";
}

inline Mesh::Property_map<VertexId, Index> fill_surface_mesh(Mesh& sm, const TriangleMesh& mesh, const char* work) {
  const Index nv = mesh.num_vertices(), nt = mesh.num_triangles();
  sm.reserve(static_cast<Mesh::size_type>(nv), static_cast<Mesh::size_type>(3 * nt / 2 + 3),
             static_cast<Mesh::size_type>(nt));
  auto source = sm.add_property_map<VertexId, Index>("v:stripweave_source", kInvalid).first;
  for (Index v = 0; v < nv; ++v) {
    const Vec3& p = mesh.positions[v];
    source[sm.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z()))] = v;
  }
  for (Index t = 0; t < nt; ++t) {
    const Tri& f = mesh.triangles[t];
    if (sm.add_face(VertexId(f[0]), VertexId(f[1]), VertexId(f[2])) == Mesh::null_face())
      throw InputError(std::string("cannot ") + work + ": triangle " + std::to_string(t) + " near " +
                       point_text(mesh.positions[f[0]]) +
                       " makes the mesh non-manifold or inconsistently oriented (sanitize the mesh first)");
  }
  return source;
}

inline TriangleMesh mesh_of(const Mesh& sm) {
  TriangleMesh out;
  out.positions.reserve(sm.number_of_vertices());
  for (VertexId v : sm.vertices()) {
    const auto& p = sm.point(v);
    out.positions.emplace_back(p.x(), p.y(), p.z());
  }
  out.triangles.reserve(sm.number_of_faces());
  for (FaceId f : sm.faces()) {
    const auto h = sm.halfedge(f);
    out.triangles.push_back({static_cast<Index>(sm.source(h).idx()), static_cast<Index>(sm.target(h).idx()),
                             static_cast<Index>(sm.target(sm.next(h)).idx())});
  }
  return out;
}

}  // namespace stripweave::cgal_mesh
