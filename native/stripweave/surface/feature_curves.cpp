#include "stripweave/surface/feature_curves.h"

#include <cmath>
#include <numeric>

namespace stripweave {

std::vector<EdgeClass> classify_edges(const MeshTopology& topo, const std::vector<bool>& is_feature) {
  std::vector<EdgeClass> classes(topo.num_edges(), EdgeClass::Regular);
  for (Index e = 0; e < topo.num_edges(); ++e) {
    if (topo.is_boundary_edge(e))
      classes[e] = EdgeClass::Boundary;
    else if (is_feature[e])
      classes[e] = EdgeClass::Feature;
  }
  return classes;
}

std::vector<bool> dihedral_feature_edges(const TriangleMesh& mesh, const MeshTopology& topo, double angle_deg) {
  const double cos_limit = std::cos(angle_deg * M_PI / 180.0);
  std::vector<bool> sharp(topo.num_edges(), false);
  for (Index e = 0; e < topo.num_edges(); ++e) {
    const auto& et = topo.edge_triangles[e];
    if (et[1] == kInvalid) continue;
    const Vec3 n0 = triangle_normal_area2(mesh, et[0]).normalized();
    const Vec3 n1 = triangle_normal_area2(mesh, et[1]).normalized();
    sharp[e] = n0.dot(n1) < cos_limit;
  }
  return sharp;
}

std::vector<FeatureCurve> chain_feature_curves(const TriangleMesh& mesh, const MeshTopology& topo,
                                               std::vector<EdgeClass>& classes, const std::vector<bool>& break_vertex,
                                               double min_length, std::vector<Index>& edge_curve) {
  const Index nv = mesh.num_vertices();
  std::vector<Index> valence(nv, 0);
  for (Index e = 0; e < topo.num_edges(); ++e)
    if (classes[e] == EdgeClass::Feature) ++valence[topo.edges[e][0]], ++valence[topo.edges[e][1]];
  auto is_end = [&](Index v) { return valence[v] != 2 || (!break_vertex.empty() && break_vertex[v]); };
  auto next_feature_edge = [&](Index v, Index not_edge, const std::vector<bool>& used) {
    for (const Index* n = topo.vertex_neighbours.begin(v); n != topo.vertex_neighbours.end(v); ++n) {
      const Index e = topo.find_edge(v, *n);
      if (e != not_edge && classes[e] == EdgeClass::Feature && !used[e]) return e;
    }
    return kInvalid;
  };

  std::vector<bool> used(topo.num_edges(), false);
  std::vector<FeatureCurve> chains;
  std::vector<std::vector<Index>> chain_edges;
  auto trace = [&](Index start, Index first_edge) {
    FeatureCurve c;
    std::vector<Index> edges;
    c.vertices.push_back(start);
    Index v = start, e = first_edge;
    while (e != kInvalid) {
      used[e] = true;
      edges.push_back(e);
      v = topo.edges[e][0] == v ? topo.edges[e][1] : topo.edges[e][0];
      if (v == start) {
        c.closed = true;
        break;
      }
      c.vertices.push_back(v);
      if (is_end(v)) break;
      e = next_feature_edge(v, e, used);
    }
    chains.push_back(std::move(c));
    chain_edges.push_back(std::move(edges));
  };
  // Open chains start at their ends; what is left are closed loops.
  for (Index v = 0; v < nv; ++v) {
    if (valence[v] == 0 || !is_end(v)) continue;
    for (Index e; (e = next_feature_edge(v, kInvalid, used)) != kInvalid;) trace(v, e);
  }
  for (Index e = 0; e < topo.num_edges(); ++e)
    if (classes[e] == EdgeClass::Feature && !used[e]) trace(topo.edges[e][0], e);

  // Drop short crease clusters: chains joined at their ends form a cluster
  // (a crease network); one whose total length is under min_length is scan
  // noise (a spike, a scratch), not a feature of the part.
  std::vector<Index> cluster(chains.size());
  std::iota(cluster.begin(), cluster.end(), 0);
  auto root = [&](Index c) {
    while (cluster[c] != c) c = cluster[c] = cluster[cluster[c]];
    return c;
  };
  std::vector<Index> chain_at(nv, kInvalid);
  for (size_t i = 0; i < chains.size(); ++i)
    for (Index v : {chains[i].vertices.front(), chains[i].vertices.back()}) {
      if (chain_at[v] == kInvalid)
        chain_at[v] = static_cast<Index>(i);
      else
        cluster[root(static_cast<Index>(i))] = root(chain_at[v]);
    }
  std::vector<double> cluster_length(chains.size(), 0.0);
  for (size_t i = 0; i < chains.size(); ++i)
    for (Index e : chain_edges[i])
      cluster_length[root(static_cast<Index>(i))] +=
          (mesh.positions[topo.edges[e][0]] - mesh.positions[topo.edges[e][1]]).norm();
  std::vector<FeatureCurve> curves;
  edge_curve.assign(topo.num_edges(), kInvalid);
  for (size_t i = 0; i < chains.size(); ++i) {
    if (cluster_length[root(static_cast<Index>(i))] < min_length) {
      for (Index e : chain_edges[i]) classes[e] = EdgeClass::Regular;
      continue;
    }
    for (Index e : chain_edges[i]) edge_curve[e] = static_cast<Index>(curves.size());
    curves.push_back(chains[i]);
  }
  return curves;
}

}  // namespace stripweave
