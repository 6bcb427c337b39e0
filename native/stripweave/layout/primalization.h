// The steps of build_quad_layout (quad_layout.h), shared among its files.
//
// PrimalContext: the arrangement's refined mesh seen as the graph the primal
//   geometry is routed on: its wedges cut open along the loops (a wedge lies
//   in one region; a path over wedges never crosses a loop), the wedge graph
//   (two wedges are joined by each triangle side between them) with a cost
//   per refined edge, and which refined edges lie on sharp features or on
//   the open boundary.
//
// place_primal_vertices  one vertex per region (rules in quad_layout.h;
//                        the balance of the region's sides in
//                        primal_vertex_balance.cpp);
//                        fills vertex_wedge (per region, the wedge it is at)
// route_primal_edges     one edge per arc (quad_layout.h)
// straighten_primal_edges  relax the edges' zig-zag on the surface; fills
//                        QuadLayout::positions
// cut_primal_patches     patches, triangle_patch, patch_wedges
// measure_crease_conformity  crease length on primal edges (issue 17)
#pragma once

#include "stripweave/layout/quad_layout.h"

#include <limits>

namespace stripweave {

struct PrimalContext {
  const Surface& surface;
  const LoopArrangement& arrangement;
  const Regions& regions;

  Wedges wedges;                          // cut along the loops
  std::vector<Index> wedge_region;        // per wedge
  Csr wedge_neighbours;                   // the wedge graph
  Csr wedge_neighbour_edge;               // per neighbour entry, the refined edge it runs along
  std::vector<double> edge_length;        // per refined edge, normalized units
  std::vector<std::uint8_t> edge_feature; // per refined edge: on a crease (surface_crease) of the surface
  std::vector<std::uint8_t> surface_crease;  // per surface edge: a crease the layout follows (creases_of)
  std::vector<std::uint8_t> vertex_on_loop, vertex_on_boundary, vertex_crossing;  // per refined vertex

  PrimalContext(const Surface& s, const LoopArrangement& a, const Regions& g);

  // Shortest paths over the wedge graph from `sources` (cost `cost(edge)`),
  // never entering a wedge for which `blocked` holds (sources excepted).
  // Returns the distance per wedge (infinity if unreached); pred receives
  // the previous wedge on the path (kInvalid at sources).
  std::vector<double> shortest_paths(const std::vector<Index>& sources, const std::function<double(Index)>& cost,
                                     const std::function<bool(Index)>& blocked, std::vector<Index>* pred) const;
  // The same search into a caller's buffers (dist per wedge, infinity where
  // not yet reached; pred, if given, sized to the wedges), appending each
  // wedge it reaches to `reached` (if given): many searches that each stay
  // in one region then cost their regions' sizes, not the mesh's, if the
  // caller resets only the reached entries.
  void grow_shortest_paths(const std::vector<Index>& sources, const std::function<double(Index)>& cost,
                           const std::function<bool(Index)>& blocked, std::vector<double>& dist,
                           std::vector<Index>* pred, std::vector<Index>* reached) const;

  // The wedges (left, right) at vertex i of arc k: the two sides of the
  // arc's edge i (edge i - 1 for the last vertex of an open arc); kInvalid
  // on a side that is the open boundary.
  std::pair<Index, Index> arc_side_wedges(Index k, size_t i) const;
};

// Per wedge, its distance from the loops within its region (normalized
// units): how centred a vertex there sits (primal_vertices.cpp).
std::vector<double> loop_clearance(const PrimalContext& ctx);
// The wedge of refined vertex v in region r (kInvalid if v is not in r).
Index wedge_at(const PrimalContext& ctx, Index v, Index r);

// Per refined vertex, 1 if it lies on a crease the layout follows.
std::vector<std::uint8_t> crease_vertices(const PrimalContext& ctx);

// Per wedge, the sum over its region's sides (a side per arc side facing
// the region) of the squared distance to that side within the region,
// normalized units squared: least at the region's balanced centre
// (primal_vertex_balance.cpp).
std::vector<double> side_balance(const PrimalContext& ctx);

// pin_primal_vertices  move the vertex of each pin's region to the pin
//                      (quad_layout.h; primal_vertex_pins.cpp)
void pin_primal_vertices(const PrimalContext& ctx, const std::vector<Vec3>& pins, std::vector<PrimalVertex>& vertices,
                         std::vector<Index>& vertex_wedge);

// The wedge off the loops (and off the crossings) whose vertex is nearest p,
// among those `allowed` (kInvalid if none is); O(wedges) (primal_vertex_pins.cpp).
Index nearest_wedge(const PrimalContext& ctx, const Vec3& p, const std::function<bool(Index)>& allowed);

// symmetrize_primal_vertices  move the vertices of regions that are images
//                      of each other under the symmetries to images of each
//                      other (quad_layout.h; primal_vertex_symmetry.cpp)
void symmetrize_primal_vertices(const PrimalContext& ctx, const std::vector<Symmetry>& symmetries,
                                std::vector<PrimalVertex>& vertices, std::vector<Index>& vertex_wedge);

std::vector<PrimalVertex> place_primal_vertices(const PrimalContext& ctx, const std::vector<Singularity>& singularities,
                                                std::vector<Index>& vertex_wedge);

// resolve_edge_routes  which edge each hand route (EdgeRoute) takes, and
//                      the wedge it goes through (primal_edge_routes.cpp)
struct ResolvedEdgeRoute {
  Index route = 0;        // in the input
  Index arc = kInvalid;   // the edge's arc
  Index wedge = kInvalid; // the point it goes through, in one of the arc's two regions
};
std::vector<ResolvedEdgeRoute> resolve_edge_routes(const PrimalContext& ctx, const std::vector<Index>& vertex_wedge,
                                                   const std::vector<EdgeRoute>& routes,
                                                   std::vector<std::string>& problems);

// route_primal_edges   one edge per arc (quad_layout.h), the resolved hand
//                      routes pinned first
std::vector<PrimalEdge> route_primal_edges(const PrimalContext& ctx, const std::vector<Index>& vertex_wedge,
                                           const std::vector<ResolvedEdgeRoute>& routes,
                                           std::vector<std::string>& problems);

// crowded_vertices     refined vertices (off the loops) where the routed
//                      edges crowd: primal vertices that an edge leaves through
//                      a neighbour another edge also passes, and vertices two
//                      edges pass (star_refinement.h; primal_vertex_stars.cpp)
std::vector<Index> crowded_vertices(const PrimalContext& ctx, const std::vector<PrimalVertex>& vertices,
                                           const std::vector<PrimalEdge>& edges);

void straighten_primal_edges(const PrimalContext& ctx, QuadLayout& layout);

void cut_primal_patches(const PrimalContext& ctx, QuadLayout& layout);

// The length of the refined edges marked in refined_crease (crease_structure.h).
double refined_crease_length(const LoopArrangement& A, const std::vector<std::uint8_t>& refined_crease);

// Fills QuadLayout::crease_conformity, crease_off_edges, crease_conforming
// (primal_crease_conformity.cpp).
void measure_crease_conformity(const PrimalContext& ctx, QuadLayout& layout);

// The refined vertices of the crease path from `from` to `to` inside region
// r (its crease edges off the loops), in order; empty if there is none.
std::vector<Index> crease_path_in_region(const PrimalContext& ctx, Index r, Index from, Index to);

}  // namespace stripweave
