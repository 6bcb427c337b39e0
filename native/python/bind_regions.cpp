// Bindings of the regions stage (paper §4.2): the loop arrangement and the
// assessment of its regions.
//
// regions(session, loops, singular_vertices=[], quarter_indices=[], details=False) -> dict
//   Embeds each loop (session.embed), splits it into per-triangle segments,
//   builds the arrangement of all loops in a refined mesh
//   (layout/loop_arrangement.h) and its regions (layout/regions.h, where the
//   valence and curvature conventions are). The singularities are the cross
//   field's (cross_field()["singularities"]): vertex ids and their indices in
//   quarters (empty quarter_indices: all 0). Runs without the GIL.
//   Keys (areas in MODEL units squared, positions in model units):
//     regions      [{"valence", "disc", "colour" (none|red|orange|yellow),
//                    "total_curvature", "ideal_valence" (4 - 2K/pi),
//                    "euler_characteristic", "boundaries", "genus", "area",
//                    "open_sides" (sides along the open boundary: one vertex
//                    closes one, regions.h),
//                    "on_open_boundary" (some of its boundary is open
//                    boundary: a sheet, not a cap, regions.h),
//                    "triangles" (refined), "singularities": [{"vertex",
//                    "index", "position"}]}]
//     valid        no region is red
//     crossings    vertices where two or more loop passes meet
//     arcs         the loops' pieces between nodes of the arrangement
//     nodes, graph_vertices, graph_edges   the arrangement graph (loops and
//                  open boundary; a cycle without nodes counts as one vertex
//                  and one edge)
//     euler_sum    graph_vertices - graph_edges + sum of the regions' chi,
//                  equal to euler_characteristic (of the surface)
//     refined_triangles, refined_euler_characteristic, snapped_points,
//     star_triangles, inverted_triangles (refined triangles facing against
//     their surface triangle), min_area_ratio (smallest refined triangle
//     area over its surface triangle's)
//     time_ms      arrangement + regions; arrangement_ms, regions_ms, embed_ms
//                  (embedding and per-triangle segments)
//   With details=True also: vertices (V,3), triangles (T,3), parent_triangle,
//   triangle_region, edges (E,2), edge_loop (E,) (a loop on the edge, or -1),
//   crossing_vertices, arc_list [{"loop", "vertices", "closed", "left",
//   "right"}]; regions_of_paths also bridge_anchors (per region,
//   [[x,y,z,dx,dy,dz], ...]: layout/weave_seeds.h, up to 3).
#include "bind_regions.h"

#include "stripweave/core/error.h"
#include "stripweave/layout/regions.h"
#include "stripweave/layout/weave_seeds.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <chrono>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

namespace {

// Per region, the weave's cut anchors (layout/weave_seeds.h, up to 3) in model
// units: for regions_of_paths' details only (tests and tools), so that the
// layout's details, which the main job's preview asks for, do not pay for them.
py::list bridge_anchor_list(const Surface& s, const Computed& c) {
  py::list out;
  for (const auto& anchors : bridge_anchors(c.arrangement, c.regions, 3)) {
    py::list per_region;
    for (const CrossingAnchor& b : anchors) {
      const Vec3 p = s.similarity.to_model(b.point);
      per_region.append(std::vector<double>{p.x(), p.y(), p.z(), b.direction.x(), b.direction.y(), b.direction.z()});
    }
    out.append(per_region);
  }
  return out;
}

py::list position(const Surface& s, const Vec3& p) {
  const Vec3 q = s.similarity.to_model(p);
  py::list out;
  for (int j = 0; j < 3; ++j) out.append(q[j]);
  return out;
}

}  // namespace

void put_region_keys(py::dict& d, const Region& r, double scale2) {
  d["valence"] = r.valence;
  d["disc"] = r.disc;
  d["colour"] = colour_name(r.colour);
  d["total_curvature"] = r.total_curvature;
  d["ideal_valence"] = ideal_valence(r.total_curvature);
  d["euler_characteristic"] = r.euler_characteristic;
  d["boundaries"] = r.boundaries;
  d["open_sides"] = r.open_sides;
  d["on_open_boundary"] = r.on_open_boundary;
  d["genus"] = r.genus;
  d["area"] = r.area * scale2;
  d["excess_extrema"] = r.excess_extrema;
  d["crease_problem"] = crease_problem_name(r.crease_problem);
  d["crease_excess"] = r.crease_excess;
  d["crease_rim_lack"] = r.crease_rim_lack;
  d["set_aside"] = r.set_aside;
}

std::vector<LoopPath> paths_from_dicts(const Surface& s, const std::vector<py::dict>& paths) {
  std::vector<LoopPath> loops;
  for (const py::dict& d : paths) {
    LoopPath lp;
    lp.path.vertex = d["vertex"].cast<std::vector<Index>>();
    lp.path.edge = d["edge"].cast<std::vector<Index>>();
    lp.path.t = d["t"].cast<std::vector<double>>();
    lp.closed = d["closed"].cast<bool>();
    const size_t n = lp.path.vertex.size();
    if (lp.path.edge.size() != n || lp.path.t.size() != n)
      throw InputError("a path needs as many edges and t as vertices");
    for (size_t i = 0; i < n; ++i) {
      const Index v = lp.path.vertex[i], e = lp.path.edge[i];
      if (v != kInvalid) {
        if (v < 0 || v >= s.mesh.num_vertices()) throw InputError("a path names a vertex the surface lacks");
        lp.path.points.push_back(s.mesh.positions[v]);
      } else {
        if (e < 0 || e >= s.topology.num_edges()) throw InputError("a path names an edge the surface lacks");
        const double t = lp.path.t[i];
        const EdgeKey& k = s.topology.edges[e];
        lp.path.points.push_back((1 - t) * s.mesh.positions[k[0]] + t * s.mesh.positions[k[1]]);
      }
    }
    loops.push_back(std::move(lp));
  }
  return loops;
}

py::dict regions_dict(const Surface& s, const std::vector<Singularity>& singular, const Computed& c, bool details) {
  const LoopArrangement& A = c.arrangement;
  const Regions& G = c.regions;
  const double scale2 = s.similarity.scale * s.similarity.scale;

  py::list regions;
  for (const Region& r : G.regions) {
    py::list sing;
    for (Index k : r.singularities) {
      py::dict item;
      item["vertex"] = singular[k].vertex;
      item["index"] = singular[k].index();
      item["position"] = position(s, s.mesh.positions[singular[k].vertex]);
      sing.append(item);
    }
    py::dict d;
    put_region_keys(d, r, scale2);
    d["triangles"] = r.triangles;
    d["singularities"] = sing;
    regions.append(d);
  }

  // Geometric sanity of the refinement, against the surface triangles.
  Index inverted = 0;
  double min_ratio = std::numeric_limits<double>::infinity();
  for (Index t = 0; t < A.mesh.num_triangles(); ++t) {
    const Vec3 n = triangle_normal_area2(A.mesh, t);
    const Vec3 parent = triangle_normal_area2(s.mesh, A.parent_triangle[t]);
    inverted += n.dot(parent) <= 0;
    if (parent.norm() > 0) min_ratio = std::min(min_ratio, n.norm() / parent.norm());
  }

  py::dict out;
  out["regions"] = regions;
  out["valid"] = G.valid;
  out["crossings"] = A.crossings;
  out["arcs"] = A.arcs.size();
  out["nodes"] = A.nodes.size();
  out["graph_vertices"] = A.graph_vertices;
  out["graph_edges"] = A.graph_edges;
  out["euler_sum"] = G.euler_sum;
  out["euler_characteristic"] = s.mesh.num_vertices() - s.topology.num_edges() + s.mesh.num_triangles();
  out["refined_triangles"] = A.mesh.num_triangles();
  out["refined_euler_characteristic"] = A.mesh.num_vertices() - A.topology.num_edges() + A.mesh.num_triangles();
  out["snapped_points"] = A.snapped_points;
  out["star_triangles"] = A.star_triangles;
  out["inverted_triangles"] = inverted;
  out["min_area_ratio"] = min_ratio;
  out["embed_ms"] = c.embed_ms;
  out["arrangement_ms"] = c.arrangement_ms;
  out["regions_ms"] = c.regions_ms;
  out["time_ms"] = c.arrangement_ms + c.regions_ms;
  if (!details) return out;

  const Index nv = A.mesh.num_vertices(), nt = A.mesh.num_triangles(), ne = A.topology.num_edges();
  py::array_t<double> vertices({static_cast<py::ssize_t>(nv), py::ssize_t(3)});
  auto V = vertices.mutable_unchecked<2>();
  for (Index v = 0; v < nv; ++v) {
    const Vec3 q = s.similarity.to_model(A.mesh.positions[v]);
    for (int j = 0; j < 3; ++j) V(v, j) = q[j];
  }
  py::array_t<std::int32_t> triangles({static_cast<py::ssize_t>(nt), py::ssize_t(3)});
  auto T = triangles.mutable_unchecked<2>();
  for (Index t = 0; t < nt; ++t)
    for (int j = 0; j < 3; ++j) T(t, j) = A.mesh.triangles[t][j];
  py::array_t<std::int32_t> edges({static_cast<py::ssize_t>(ne), py::ssize_t(2)});
  auto E = edges.mutable_unchecked<2>();
  std::vector<Index> edge_loop(ne, kInvalid);
  for (Index e = 0; e < ne; ++e) {
    E(e, 0) = A.topology.edges[e][0], E(e, 1) = A.topology.edges[e][1];
    if (A.on_loop(e)) edge_loop[e] = A.labels[*A.edge_labels.begin(e)].loop;
  }
  std::vector<Index> crossing_vertices;
  for (const ArrangementNode& node : A.nodes)
    if (node.crossing()) crossing_vertices.push_back(node.vertex);
  py::list arcs;
  for (size_t k = 0; k < A.arcs.size(); ++k) {
    py::dict d;
    d["loop"] = A.arcs[k].loop;
    d["vertices"] = A.arcs[k].vertices;
    d["closed"] = A.arcs[k].closed;
    d["left"] = G.arc_left[k];
    d["right"] = G.arc_right[k];
    arcs.append(d);
  }
  out["vertices"] = vertices;
  out["triangles"] = triangles;
  out["parent_triangle"] = A.parent_triangle;
  out["triangle_region"] = G.triangle_region;
  out["edges"] = edges;
  out["edge_loop"] = edge_loop;
  out["crossing_vertices"] = crossing_vertices;
  out["arc_list"] = arcs;
  return out;
}

std::vector<Singularity> singularities_from(const Surface& s, const std::vector<Index>& vertices,
                                           const std::vector<int>& quarter_indices) {
  if (!quarter_indices.empty() && quarter_indices.size() != vertices.size())
    throw InputError("quarter_indices must be empty or give one index per singular vertex");
  std::vector<Singularity> out;
  for (size_t k = 0; k < vertices.size(); ++k) {
    if (vertices[k] < 0 || vertices[k] >= s.mesh.num_vertices())
      throw InputError("singular vertex " + std::to_string(vertices[k]) + " is not a surface vertex");
    out.push_back({vertices[k], quarter_indices.empty() ? 0 : quarter_indices[k]});
  }
  return out;
}

std::vector<LoopPath> embed_loops(const LoopSession& session, const std::vector<Loop>& loops) {
  std::vector<LoopPath> paths;
  for (const Loop& loop : loops) {
    LoopPath lp;
    lp.path = session.embed(loop);
    lp.closed = loop.closed;
    paths.push_back(std::move(lp));
  }
  return paths;
}

void bind_regions(py::module_& m) {
  m.def("regions", [](const LoopSession& session, const std::vector<Loop>& loops,
                      const std::vector<Index>& singular_vertices, const std::vector<int>& quarter_indices,
                      bool details) {
        const Surface& s = session.surface();
        const std::vector<Singularity> singular = singularities_from(s, singular_vertices, quarter_indices);
        Computed c;
        {
          stripweave_python::NativeCall release;
          const auto t0 = Clock::now();
          std::vector<LoopPath> paths = embed_loops(session, loops);
          const double embed_ms = millis(t0, Clock::now());
          c = arrange_loops(s, paths, singular);
          c.embed_ms += embed_ms;
        }
        return regions_dict(s, singular, c, details);
      },
      py::arg("session"), py::arg("loops"), py::arg("singular_vertices") = std::vector<Index>(),
      py::arg("quarter_indices") = std::vector<int>(), py::arg("details") = false,
      "The loops' arrangement and its regions with the assessment colours of paper §4.2 (areas in model units^2)");

  m.def("regions_of_paths", [](const Surface& s, const std::vector<py::dict>& paths,
                               const std::vector<Index>& singular_vertices, const std::vector<int>& quarter_indices,
                               bool details) {
        const std::vector<Singularity> singular = singularities_from(s, singular_vertices, quarter_indices);
        std::vector<LoopPath> loops = paths_from_dicts(s, paths);
        Computed c;
        {
          stripweave_python::NativeCall release;
          c = arrange_loops(s, loops, singular);
        }
        py::dict out = regions_dict(s, singular, c, details);
        if (details) out["bridge_anchors"] = bridge_anchor_list(s, c);
        return out;
      },
      py::arg("surface"), py::arg("paths"), py::arg("singular_vertices") = std::vector<Index>(),
      py::arg("quarter_indices") = std::vector<int>(), py::arg("details") = false,
      "regions() for loops given as embedded paths: dicts with per point 'vertex' (or -1), 'edge' (or -1) and "
      "'t' along surface.edges[edge], and 'closed' (for tests and tools)");
}

}  // namespace stripweave_python
