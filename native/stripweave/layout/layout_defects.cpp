// The strict checks of a quad layout (see layout_defects.h).
#include "stripweave/layout/layout_defects.h"

#include "stripweave/layout/crease_structure.h"

#include "stripweave/layout/quad_layout.h"
#include "stripweave/surface/corner_strength.h"
#include "stripweave/surface/creases.h"

#include <algorithm>
#include <limits>
#include <queue>
#include <set>
#include <tuple>

namespace stripweave {

const char* defect_name(DefectKind kind) {
  switch (kind) {
    case DefectKind::NonQuad: return "non_quad";
    case DefectKind::OverlappingEdges: return "overlapping_edges";
    case DefectKind::Valence2: return "valence2";
    case DefectKind::HighValence: return "high_valence";
    case DefectKind::Creased: return "creased";
    case DefectKind::Degenerate: return "degenerate";
    case DefectKind::Uncovered: return "uncovered";
  }
  return "non_quad";
}

namespace {

struct Checker {
  const Surface& s;
  const LoopArrangement& A;
  const QuadLayout& L;
  const std::vector<std::uint8_t>& crease;  // per surface edge (creases_of)
  LayoutDefects& out;

  Vec3 model(const Vec3& p) const { return s.similarity.to_model(p); }

  void add(DefectKind kind, const Vec3& normalized, Index patch, Index vertex, Index edge = kInvalid,
           Index other = kInvalid) {
    DefectLocation d;
    d.kind = kind;
    d.position = model(normalized);
    d.patch = patch, d.vertex = vertex, d.edge = edge, d.other_edge = other;
    out.locations.push_back(d);
  }

  // The patch's vertex nearest its area centroid: a point on the surface
  // (a curved patch's centroid lies off it).
  Vec3 patch_point(const PrimalPatch& p) const {
    Vec3 centroid = Vec3::Zero();
    double area = 0;
    for (Index t : p.triangles) {
      const Tri& f = A.mesh.triangles[t];
      const Vec3 &a = L.positions[f[0]], &b = L.positions[f[1]], &c = L.positions[f[2]];
      const double w = 0.5 * (b - a).cross(c - a).norm() + 1e-300;
      centroid += w * (a + b + c) / 3.0;
      area += w;
    }
    if (area <= 0) return Vec3::Zero();
    centroid /= area;
    Vec3 best = L.positions[A.mesh.triangles[p.triangles.front()][0]];
    for (Index t : p.triangles)
      for (Index v : A.mesh.triangles[t])
        if ((L.positions[v] - centroid).squaredNorm() < (best - centroid).squaredNorm()) best = L.positions[v];
    return best;
  }

  void patch_kind(Index p, DefectKind kind, Index& count) {
    out.patch_defects[p].push_back(kind);
    ++count;
    add(kind, patch_point(L.patches[p]), p, kInvalid);
  }

  // Mean solver-mesh edge length (normalized units): the mesh's resolution.
  double mean_edge() const {
    double length = 0;
    for (const EdgeKey& e : s.topology.edges) length += (s.mesh.positions[e[0]] - s.mesh.positions[e[1]]).norm();
    return s.topology.num_edges() ? length / s.topology.num_edges() : 0.0;
  }

  // Four corners at primal vertices, and four sides none of which collapses
  // to a point (shorter than one solver edge: the two corners it joins are
  // then one corner). Corners may coincide where a side is a closed edge of
  // positive length, as on a torus's one-patch layout (paper §2: a quad
  // layout of one patch), whose fit is an ordinary four-sided patch.
  // A side may not come straight back along the side before it (the same
  // edge, run the other way): the patch then folds around a slit, whose tip
  // is a corner of 360 degrees at a vertex of valence 1 (a loop that curls
  // across itself bounds a lobe of one arc; the patch at the crossing wraps
  // around the lobe's dangling edge). A torus's one patch runs each closed
  // edge twice too, but never one right after the other.
  bool four_corners(const PrimalPatch& patch, double min_side) const {
    for (int k = 0; k < 4; ++k) {
      if (patch.corners[k] == kInvalid || patch.edges[k] == kInvalid) return false;
      if (L.edges[patch.edges[k]].length < min_side) return false;
    }
    return !patch.folds_back();
  }

  // h: the mean solver edge (mean_edge), the resolution both shape rules use.
  void check_patch_shapes(double h) {
    const double min_side = h;
    for (size_t p = 0; p < L.patches.size(); ++p) {
      const PrimalPatch& patch = L.patches[p];
      if (!patch.quad || !four_corners(patch, min_side))
        patch_kind(static_cast<Index>(p), DefectKind::NonQuad, out.non_quad_patches);
      if (patch.creased()) patch_kind(static_cast<Index>(p), DefectKind::Creased, out.creased_patches);
    }
  }

  // Primal edges meeting away from a primal vertex both end at.
  void check_overlaps() {
    struct Visit {
      Index vertex, edge, end;  // end: the primal vertex if the visit is an end of the path, else kInvalid
    };
    std::vector<Visit> visits;
    for (size_t e = 0; e < L.edges.size(); ++e) {
      const PrimalEdge& pe = L.edges[e];
      for (size_t i = 0; i < pe.path.size(); ++i) {
        const Index end = i == 0 ? pe.v0 : i + 1 == pe.path.size() ? pe.v1 : kInvalid;
        visits.push_back({pe.path[i], static_cast<Index>(e), end});
      }
    }
    std::sort(visits.begin(), visits.end(),
              [](const Visit& a, const Visit& b) { return std::tie(a.vertex, a.edge) < std::tie(b.vertex, b.edge); });
    // A meeting at x is fine when both visits end their paths at one primal vertex sitting at x.
    auto shared_end = [&](const Visit& a, const Visit& b) {
      return a.end != kInvalid && a.end == b.end && L.vertices[a.end].refined_vertex == a.vertex;
    };
    std::set<std::pair<Index, Index>> pairs;
    std::vector<std::uint8_t> involved(L.edges.size(), 0);
    for (size_t i = 0; i < visits.size();) {
      size_t j = i;
      while (j < visits.size() && visits[j].vertex == visits[i].vertex) ++j;
      for (size_t a = i; a < j; ++a) {
        for (size_t b = a + 1; b < j; ++b) {
          if (shared_end(visits[a], visits[b])) continue;
          const std::pair<Index, Index> key{visits[a].edge, visits[b].edge};
          involved[key.first] = involved[key.second] = 1;
          if (pairs.insert(key).second)
            add(DefectKind::OverlappingEdges, L.positions[visits[a].vertex], kInvalid, kInvalid, key.first, key.second);
        }
      }
      i = j;
    }
    for (size_t e = 0; e < L.edges.size(); ++e) {
      if (!involved[e]) continue;
      ++out.overlapping_edges;
      out.edge_defects[e].push_back(DefectKind::OverlappingEdges);
    }
    for (size_t p = 0; p < L.patches.size(); ++p)
      for (Index e : L.patches[p].edges)
        if (e != kInvalid && involved[e]) {
          out.patch_defects[p].push_back(DefectKind::OverlappingEdges);
          break;
        }
  }

  // Per primal vertex, the valence the part forces (layout_defects.h).
  void forced_valences() {
    const std::vector<double> corner = corner_strength(s, crease);
    std::vector<int> curves(s.mesh.num_vertices(), 0);  // crease and boundary edges at each surface vertex
    for (Index e = 0; e < s.topology.num_edges(); ++e)
      if (crease[e] || s.topology.is_boundary_edge(e))
        for (Index v : s.topology.edges[e]) ++curves[v];
    out.vertex_forced_valence.assign(L.vertices.size(), 0);
    for (size_t v = 0; v < L.vertices.size(); ++v) {
      const Index r = L.vertices[v].refined_vertex;
      const Index ov = r == kInvalid ? kInvalid : A.original_vertex[r];
      if (ov != kInvalid && corner[ov] > 0) out.vertex_forced_valence[v] = curves[ov];
    }
  }

  void check_vertices() {
    forced_valences();
    for (size_t v = 0; v < L.vertices.size(); ++v) {
      const PrimalVertex& pv = L.vertices[v];
      const int forced = out.vertex_forced_valence[v];
      DefectKind kind;
      Index* count;
      if (pv.valence >= 1 && pv.valence <= 2 && forced < 2) {  // 1: the tip of a dangling edge
        kind = DefectKind::Valence2, count = &out.valence2_vertices;
      } else if (pv.valence > std::max(kMaxFreeValence, forced)) {
        kind = DefectKind::HighValence, count = &out.high_valence_vertices;
      } else {
        continue;
      }
      ++*count;
      out.vertex_defects[v].push_back(kind);
      add(kind, pv.position, kInvalid, static_cast<Index>(v));
    }
  }

  // Per refined vertex, the distance (along refined edges that are not in
  // `cut`) to the nearest endpoint of a `cut` edge: multi-source Dijkstra,
  // the sources at distance 0.
  std::vector<double> distance_from(const std::vector<std::uint8_t>& cut) const {
    const MeshTopology& rt = A.topology;
    const Index nv = A.mesh.num_vertices(), ne = rt.num_edges();
    std::vector<double> dist(nv, std::numeric_limits<double>::infinity());
    using Item = std::pair<double, Index>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    for (Index e = 0; e < ne; ++e)
      if (cut[e])
        for (Index v : rt.edges[e])
          if (dist[v] != 0) dist[v] = 0, heap.push({0.0, v});
    // Adjacency over the uncut edges.
    std::vector<Index> offsets(nv + 1, 0), next;
    for (Index e = 0; e < ne; ++e)
      if (!cut[e]) ++offsets[rt.edges[e][0] + 1], ++offsets[rt.edges[e][1] + 1];
    for (Index v = 0; v < nv; ++v) offsets[v + 1] += offsets[v];
    next.resize(offsets.back());
    std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
    for (Index e = 0; e < ne; ++e)
      if (!cut[e]) next[fill[rt.edges[e][0]]++] = rt.edges[e][1], next[fill[rt.edges[e][1]]++] = rt.edges[e][0];
    const auto& P = L.positions;  // after straightening, as the patches are measured
    while (!heap.empty()) {
      const auto [d, v] = heap.top();
      heap.pop();
      if (d > dist[v]) continue;
      for (Index k = offsets[v]; k < offsets[v + 1]; ++k) {
        const Index w = next[k];
        const double nd = d + (P[v] - P[w]).norm();
        if (nd < dist[w]) dist[w] = nd, heap.push({nd, w});
      }
    }
    return dist;
  }

  // Per patch, the largest of `dist` over its triangles' vertices.
  std::vector<double> patch_maximum(const std::vector<double>& dist) const {
    std::vector<double> out_max(L.patches.size(), 0.0);
    for (size_t p = 0; p < L.patches.size(); ++p)
      for (Index t : L.patches[p].triangles)
        for (Index v : A.mesh.triangles[t]) out_max[p] = std::max(out_max[p], dist[v]);
    return out_max;
  }

  // Per patch, the largest distance of its vertices from its boundary.
  void patch_inradii() {
    const MeshTopology& rt = A.topology;
    const Index ne = rt.num_edges();
    std::vector<std::uint8_t> cut(ne, 0);
    for (Index e = 0; e < ne; ++e) {
      const auto& et = rt.edge_triangles[e];
      cut[e] = et[1] == kInvalid || L.triangle_patch[et[0]] != L.triangle_patch[et[1]];
    }
    for (const PrimalEdge& pe : L.edges)
      for (size_t i = 0; i + 1 < pe.path.size(); ++i) {
        const Index e = rt.find_edge(pe.path[i], pe.path[i + 1]);
        if (e != kInvalid) cut[e] = 1;
      }
    out.patch_inradius = patch_maximum(distance_from(cut));
  }

  // Per patch, the largest distance of its vertices from a crease or the
  // open boundary: the width the part itself leaves a patch there. A patch
  // between two creases closer than kDegenerateRadius solver edges (the
  // side wall of a thin plate, a narrow chamfer) is as narrow as the part's
  // face, and no layout can make it wider.
  std::vector<double> crease_widths() const {
    std::vector<std::uint8_t> sharp = refined_crease_edges(s, A);
    const MeshTopology& rt = A.topology;
    for (Index e = 0; e < rt.num_edges(); ++e)
      if (rt.edge_triangles[e][1] == kInvalid) sharp[e] = 1;
    return patch_maximum(distance_from(sharp));
  }

  void check_degenerate(double h) {
    patch_inradii();
    const std::vector<double> width = crease_widths();
    double area = 0;
    for (Index t = 0; t < s.mesh.num_triangles(); ++t) {
      const Tri& f = s.mesh.triangles[t];
      const auto& P = s.mesh.positions;
      area += 0.5 * (P[f[1]] - P[f[0]]).cross(P[f[2]] - P[f[0]]).norm();
    }
    for (size_t p = 0; p < L.patches.size(); ++p) {
      const double r = out.patch_inradius[p];
      // Narrow by the part (its inradius is nearly all the width its creases
      // leave it: kForcedWidth), not by the layout: not degenerate for that.
      const bool forced = r >= kForcedWidth * width[p];
      if (L.patches[p].area < kDegenerateArea * area || (r < kDegenerateRadius * h && !forced))
        patch_kind(static_cast<Index>(p), DefectKind::Degenerate, out.degenerate_patches);
    }
  }

  void check_coverage() {
    const Index nt = s.mesh.num_triangles();
    std::vector<std::uint8_t> cover(A.mesh.num_triangles(), 0), uncovered(nt, 0);
    for (const PrimalPatch& p : L.patches)
      for (Index t : p.triangles) cover[t] = static_cast<std::uint8_t>(std::min(cover[t] + 1, 2));
    for (Index t = 0; t < A.mesh.num_triangles(); ++t)
      if (cover[t] != 1) uncovered[A.parent_triangle[t]] = 1;
    std::vector<Index> piece;
    const Index pieces = triangle_components(s.topology, nt, piece, [&](Index e) {
      const auto& et = s.topology.edge_triangles[e];
      return et[1] == kInvalid || uncovered[et[0]] != uncovered[et[1]];
    });
    std::vector<Vec3> centroid(pieces, Vec3::Zero());
    std::vector<Index> size(pieces, 0), nearest(pieces, kInvalid);
    auto centre = [&](Index t) {
      const Tri& f = s.mesh.triangles[t];
      return Vec3((s.mesh.positions[f[0]] + s.mesh.positions[f[1]] + s.mesh.positions[f[2]]) / 3.0);
    };
    for (Index t = 0; t < nt; ++t)
      if (uncovered[t]) centroid[piece[t]] += centre(t), ++size[piece[t]], ++out.uncovered_triangles;
    for (Index t = 0; t < nt; ++t) {
      if (!uncovered[t]) continue;
      const Index c = piece[t];
      const Vec3 mid = centroid[c] / size[c];
      if (nearest[c] == kInvalid || (centre(t) - mid).squaredNorm() < (centre(nearest[c]) - mid).squaredNorm())
        nearest[c] = t;
    }
    for (Index c = 0; c < pieces; ++c) {
      if (size[c] == 0) continue;
      add(DefectKind::Uncovered, centre(nearest[c]), kInvalid, kInvalid);
      out.locations.back().triangles = size[c];
    }
  }
};

}  // namespace

LayoutDefects find_layout_defects(const Surface& s, const LoopArrangement& A, const QuadLayout& L,
                                  const std::vector<std::uint8_t>& crease) {
  LayoutDefects out;
  out.patch_defects.resize(L.patches.size());
  out.vertex_defects.resize(L.vertices.size());
  out.edge_defects.resize(L.edges.size());
  const std::vector<std::uint8_t> computed =
      crease.empty() && !L.vertices.empty() ? creases_of(s) : std::vector<std::uint8_t>();
  Checker c{s, A, L, crease.empty() ? computed : crease, out};
  const double h = c.mean_edge();
  c.check_patch_shapes(h);
  c.check_overlaps();
  if (!L.vertices.empty()) c.check_vertices();
  if (!L.patches.empty()) c.check_degenerate(h);
  c.check_coverage();
  return out;
}

}  // namespace stripweave
