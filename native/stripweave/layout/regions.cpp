// The regions of a loop arrangement and their assessment (see the header).
#include "stripweave/layout/regions.h"

#include "stripweave/layout/cut_wedges.h"
#include "stripweave/surface/angle_defects.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace stripweave {

namespace {

double corner_angle(const Vec3& at, const Vec3& a, const Vec3& b) {
  const Vec3 u = a - at, w = b - at;
  return std::atan2(u.cross(w).norm(), u.dot(w));
}

// True if the loop passes straight through vertex b from edge `in` to edge
// `out` (consecutive edges of one chain), i.e. a region's boundary that
// follows them has no corner at b.
bool continues(const LoopArrangement& A, Index in, Index out, Index b) {
  for (const Index* x = A.edge_labels.begin(in); x != A.edge_labels.end(in); ++x) {
    for (const Index* y = A.edge_labels.begin(out); y != A.edge_labels.end(out); ++y) {
      const LoopLabel& p = A.labels[*x];
      const LoopLabel& q = A.labels[*y];
      if (p.loop != q.loop) continue;
      const LoopChain& c = A.chains[p.loop];
      const Index n = static_cast<Index>(c.edges.size());
      auto joint = [&](Index first) { return c.vertices[(first + 1) % c.vertices.size()]; };  // between first, first+1
      if (q.position == p.position + 1 || (c.closed && q.position == 0 && p.position == n - 1))
        if (joint(p.position) == b) return true;
      if (p.position == q.position + 1 || (c.closed && p.position == 0 && q.position == n - 1))
        if (joint(q.position) == b) return true;
    }
  }
  return false;
}

}  // namespace

Regions compute_regions(const Surface& s, const LoopArrangement& A, const std::vector<Singularity>& singularities,
                        const std::vector<std::uint8_t>& set_aside) {
  Regions out;
  const TriangleMesh& m = A.mesh;
  const MeshTopology& rt = A.topology;
  const Index nt = m.num_triangles(), nv = m.num_vertices();
  const Index surface_vertices = s.mesh.num_vertices();

  // Components across edges that separate nothing.
  const Index count = triangle_components(rt, nt, out.triangle_region, [&](Index e) { return A.separates(e); });
  out.regions.resize(count);
  const auto& region = out.triangle_region;
  std::vector<Region>& R = out.regions;
  const Index nr = static_cast<Index>(R.size());

  // Faces, area, boundary half-edges and interior vertices: chi of the
  // cut-open region is V - E + F with V = interior vertices + boundary
  // half-edges (one cut-open vertex starts each) and E = (3F + B) / 2.
  std::vector<Index> boundary_halfedges(nr, 0), interior_vertices(nr, 0);
  for (Index t = 0; t < nt; ++t) {
    Region& r = R[region[t]];
    if (!set_aside.empty() && set_aside[A.parent_triangle[t]]) r.set_aside = true;
    ++r.triangles;
    r.area += 0.5 * triangle_normal_area2(m, t).norm();
    for (Index e : rt.triangle_edges[t]) boundary_halfedges[region[t]] += A.separates(e);
  }
  for (Index v = 0; v < nv; ++v)
    if (A.degree[v] == 0 && rt.vertex_triangles.size(v) > 0) ++interior_vertices[region[*rt.vertex_triangles.begin(v)]];
  for (Index k = 0; k < nr; ++k) {
    const Index twice = 2 * interior_vertices[k] + boundary_halfedges[k] - R[k].triangles;
    if (twice % 2 != 0) throw std::logic_error("compute_regions: a region's edges do not pair up");
    R[k].euler_characteristic = twice / 2;
  }

  // Boundary cycles and their corners. A boundary half-edge (t, i) runs from
  // corner i to i+1 of t with the region on its left; the next one starts at
  // the same vertex after turning through the region's triangles there.
  std::vector<std::uint8_t> visited(3 * static_cast<size_t>(nt), 0);
  for (Index t0 = 0; t0 < nt; ++t0) {
    for (int i0 = 0; i0 < 3; ++i0) {
      if (visited[3 * t0 + i0] || !A.separates(rt.triangle_edges[t0][i0])) continue;
      Index t = t0;
      int i = i0, corners = 0, open_sides = 0;
      bool open = false;
      do {
        visited[3 * t + i] = 1;
        const Index in = rt.triangle_edges[t][i];
        const Index b = m.triangles[t][(i + 1) % 3];
        Index u = t;
        int j = (i + 1) % 3;
        for (Index guard = 0; !A.separates(rt.triangle_edges[u][j]); ++guard) {
          if (guard > nt) throw std::logic_error("compute_regions: a vertex fan does not close");
          const auto& et = rt.edge_triangles[rt.triangle_edges[u][j]];
          u = et[0] == u ? et[1] : et[0];
          const Tri& g = m.triangles[u];
          j = g[0] == b ? 0 : g[1] == b ? 1 : 2;
        }
        const Index out_edge = rt.triangle_edges[u][j];
        const bool loop_in = A.on_loop(in), loop_out = A.on_loop(out_edge);
        if (in != out_edge && (loop_in || loop_out) && !(loop_in && loop_out && continues(A, in, out_edge, b)))
          ++corners;
        if (in != out_edge && loop_in && !loop_out) ++open_sides;  // a stretch of open boundary starts
        open = open || !loop_in;  // a separating edge on no loop is the open boundary
        t = u, i = j;
      } while (t != t0 || i != i0);
      ++R[region[t0]].boundaries;
      R[region[t0]].valence += corners;
      R[region[t0]].open_sides += open_sides;
      R[region[t0]].on_open_boundary |= open;
    }
  }

  // Total curvature: each surface vertex's angle defect, shared by angle.
  const std::vector<double> vertex_defect = angle_defects(s.mesh, s.topology);
  std::vector<double> refined_sum(surface_vertices, 0.0);
  std::vector<double> angles(3 * static_cast<size_t>(nt), 0.0);
  for (Index t = 0; t < nt; ++t) {
    const Tri& f = m.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (f[k] >= surface_vertices) continue;  // refined vertices lie where the surface is flat
      angles[3 * t + k] = corner_angle(m.positions[f[k]], m.positions[f[(k + 1) % 3]], m.positions[f[(k + 2) % 3]]);
      refined_sum[f[k]] += angles[3 * t + k];
    }
  }
  // Per singular vertex, the angle each region has there.
  std::vector<Index> singular_slot(surface_vertices, kInvalid);
  std::vector<std::vector<std::pair<Index, double>>> singular_share;
  for (const Singularity& sg : singularities) {
    if (sg.vertex < 0 || sg.vertex >= surface_vertices) throw std::invalid_argument("compute_regions: a singularity names no surface vertex");
    if (singular_slot[sg.vertex] == kInvalid) {
      singular_slot[sg.vertex] = static_cast<Index>(singular_share.size());
      singular_share.emplace_back();
    }
  }
  for (Index t = 0; t < nt; ++t) {
    const Tri& f = m.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const Index v = f[k];
      if (v >= surface_vertices || refined_sum[v] <= 0) continue;
      const double share = angles[3 * t + k] / refined_sum[v];
      R[region[t]].total_curvature += vertex_defect[v] * share;
      if (singular_slot[v] != kInvalid) {
        auto& shares = singular_share[singular_slot[v]];
        auto it = std::find_if(shares.begin(), shares.end(), [&](const auto& x) { return x.first == region[t]; });
        if (it == shares.end()) shares.emplace_back(region[t], share);
        else it->second += share;
      }
    }
  }
  for (size_t k = 0; k < singularities.size(); ++k) {
    const auto& shares = singular_share[singular_slot[singularities[k].vertex]];
    if (shares.empty()) continue;
    const auto best = std::max_element(shares.begin(), shares.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    R[best->first].singularities.push_back(static_cast<Index>(k));
  }

  // Topology, colours, validity, and the Euler check.
  out.valid = true;
  out.euler_sum = A.graph_vertices - A.graph_edges;
  out.creases = crease_structure(s, A, out.triangle_region, nr);
  for (Index k = 0; k < nr; ++k) {
    Region& r = R[k];
    r.genus = (2 - r.euler_characteristic - r.boundaries) / 2;
    r.disc = r.euler_characteristic == 1 && r.boundaries == 1;
    std::vector<int> quarters;
    for (Index i : r.singularities) quarters.push_back(singularities[i].quarter_index);
    r.excess_extrema = excess_extrema(quarters);
    const RegionCreases& rc = out.creases.regions[k];
    // A rim crossed too seldom keeps the region from conforming even where its star test passes.
    r.crease_problem = rc.problem != CreaseProblem::None ? rc.problem
                       : rc.rim_lack > 0                 ? CreaseProblem::RimUncrossed
                                                         : CreaseProblem::None;
    r.crease_excess = rc.excess;
    r.crease_rim_lack = rc.rim_lack;
    r.colour = assess_region(r.disc, r.crease_problem != CreaseProblem::None, r.excess_extrema, r.valence,
                             r.total_curvature);
    out.valid &= r.set_aside || r.colour != RegionColour::Red;
    out.euler_sum += r.euler_characteristic;
  }
  for (const LoopArc& arc : A.arcs) {
    out.arc_left.push_back(arc.left_triangle == kInvalid ? kInvalid : region[arc.left_triangle]);
    out.arc_right.push_back(arc.right_triangle == kInvalid ? kInvalid : region[arc.right_triangle]);
  }
  return out;
}

}  // namespace stripweave
