#include "stripweave/surface/mesh_topology.h"

#include "stripweave/core/error.h"

#include <algorithm>
#include <numeric>
#include <sstream>

namespace stripweave {

namespace {

Csr build_csr(Index rows, const std::vector<std::pair<Index, Index>>& pairs) {
  Csr csr;
  csr.offsets.assign(rows + 1, 0);
  for (const auto& [r, _] : pairs) ++csr.offsets[r + 1];
  std::partial_sum(csr.offsets.begin(), csr.offsets.end(), csr.offsets.begin());
  csr.indices.resize(pairs.size());
  std::vector<Index> fill(csr.offsets.begin(), csr.offsets.end() - 1);
  for (const auto& [r, c] : pairs) csr.indices[fill[r]++] = c;
  return csr;
}

std::string where(const Vec3& p) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

}  // namespace

Index MeshTopology::find_edge(Index a, Index b) const {
  auto it = edge_index_.find(pack_edge(edge_key(a, b)));
  return it == edge_index_.end() ? kInvalid : it->second;
}

MeshTopology MeshTopology::build(const TriangleMesh& mesh) {
  MeshTopology topo;
  const Index nt = mesh.num_triangles();
  topo.triangle_edges.resize(nt);
  topo.edge_index_.reserve(static_cast<size_t>(nt) * 3 / 2 + 8);
  Index overloaded = 0;
  Index first_overloaded = kInvalid;
  for (Index t = 0; t < nt; ++t) {
    const Tri& f = mesh.triangles[t];
    for (int i = 0; i < 3; ++i) {
      const EdgeKey k = edge_key(f[i], f[(i + 1) % 3]);
      auto [it, inserted] = topo.edge_index_.emplace(pack_edge(k), static_cast<Index>(topo.edges.size()));
      if (inserted) {
        topo.edges.push_back(k);
        topo.edge_triangles.push_back({t, kInvalid});
      } else {
        auto& et = topo.edge_triangles[it->second];
        if (et[1] == kInvalid) {
          et[1] = t;
        } else {
          if (overloaded++ == 0) first_overloaded = k[0];
        }
      }
      topo.triangle_edges[t][i] = it->second;
    }
  }
  if (overloaded > 0) {
    std::ostringstream msg;
    msg << "non-manifold mesh: " << overloaded << " edge" << (overloaded > 1 ? "s are" : " is")
        << " shared by more than two triangles, first near " << where(mesh.positions[first_overloaded]);
    throw InputError(msg.str());
  }
  std::vector<std::pair<Index, Index>> vt;
  vt.reserve(static_cast<size_t>(nt) * 3);
  for (Index t = 0; t < nt; ++t)
    for (Index v : mesh.triangles[t]) vt.emplace_back(v, t);
  topo.vertex_triangles = build_csr(mesh.num_vertices(), vt);
  std::vector<std::pair<Index, Index>> vv;
  vv.reserve(topo.edges.size() * 2);
  for (const EdgeKey& e : topo.edges) {
    vv.emplace_back(e[0], e[1]);
    vv.emplace_back(e[1], e[0]);
  }
  topo.vertex_neighbours = build_csr(mesh.num_vertices(), vv);
  return topo;
}

Index triangle_components(const MeshTopology& topo, Index num_triangles, std::vector<Index>& component) {
  return triangle_components(topo, num_triangles, component, [](Index) { return false; });
}

Index triangle_components(const MeshTopology& topo, Index num_triangles, std::vector<Index>& component,
                          const std::function<bool(Index)>& is_cut) {
  component.assign(num_triangles, kInvalid);
  Index count = 0;
  std::vector<Index> stack;
  for (Index seed = 0; seed < num_triangles; ++seed) {
    if (component[seed] != kInvalid) continue;
    component[seed] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      const Index t = stack.back();
      stack.pop_back();
      for (Index e : topo.triangle_edges[t]) {
        if (is_cut(e)) continue;
        for (Index n : topo.edge_triangles[e])
          if (n != kInvalid && component[n] == kInvalid) {
            component[n] = count;
            stack.push_back(n);
          }
      }
    }
    ++count;
  }
  return count;
}

std::vector<std::vector<Index>> boundary_loops(const TriangleMesh& mesh, const MeshTopology& topo) {
  // Each boundary edge, directed as in its triangle, maps its tail to its head.
  // On a manifold mesh (no pinched vertices) every boundary vertex has one
  // outgoing boundary edge, so following the map traces the loops.
  std::unordered_map<Index, Index> next;
  for (Index e = 0; e < topo.num_edges(); ++e) {
    if (!topo.is_boundary_edge(e)) continue;
    const Tri& f = mesh.triangles[topo.edge_triangles[e][0]];
    for (int i = 0; i < 3; ++i) {
      const Index a = f[i], b = f[(i + 1) % 3];
      if (edge_key(a, b) == topo.edges[e]) next.emplace(a, b);
    }
  }
  std::vector<std::vector<Index>> loops;
  std::unordered_map<Index, bool> used;
  std::vector<Index> starts;
  for (const auto& [a, _] : next) starts.push_back(a);
  std::sort(starts.begin(), starts.end());  // deterministic loop order
  for (Index start : starts) {
    if (used[start]) continue;
    std::vector<Index> loop;
    Index v = start;
    while (!used[v]) {
      used[v] = true;
      loop.push_back(v);
      auto it = next.find(v);
      if (it == next.end()) break;
      v = it->second;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

std::vector<Index> vertex_fans(const MeshTopology& topo, Index v, Index& fans) {
  const Index n = topo.vertex_triangles.size(v);
  const Index* tris = topo.vertex_triangles.begin(v);
  std::vector<Index> label(n, kInvalid);
  fans = 0;
  for (Index s = 0; s < n; ++s) {
    if (label[s] != kInvalid) continue;
    label[s] = fans;
    std::vector<Index> stack{s};
    while (!stack.empty()) {
      const Index i = stack.back();
      stack.pop_back();
      for (Index e : topo.triangle_edges[tris[i]]) {
        if (topo.edges[e][0] != v && topo.edges[e][1] != v) continue;
        for (Index nt : topo.edge_triangles[e]) {
          if (nt == kInvalid) continue;
          for (Index j = 0; j < n; ++j)
            if (tris[j] == nt && label[j] == kInvalid) {
              label[j] = fans;
              stack.push_back(j);
            }
        }
      }
    }
    ++fans;
  }
  return label;
}

std::vector<std::pair<Index, Index>> non_manifold_vertices(const TriangleMesh& mesh, const MeshTopology& topo) {
  std::vector<std::pair<Index, Index>> result;
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    Index fans = 0;
    if (topo.vertex_triangles.size(v) > 1) vertex_fans(topo, v, fans);
    if (fans > 1) result.emplace_back(v, fans);
  }
  return result;
}

std::vector<std::vector<Index>> split_pinched_vertices(TriangleMesh& m, const MeshTopology& topo) {
  const auto pinched = non_manifold_vertices(m, topo);
  std::vector<std::vector<Index>> out;
  for (const auto& pinch : pinched) {
    const Index v = pinch.first;
    const std::vector<Index> tris(topo.vertex_triangles.begin(v), topo.vertex_triangles.end(v));
    Index count = 0;
    const std::vector<Index> fan = vertex_fans(topo, v, count);
    std::vector<Index> copy(count, v);
    for (Index c = 1; c < count; ++c) {
      copy[c] = m.num_vertices();
      m.positions.push_back(m.positions[v]);
    }
    for (size_t i = 0; i < tris.size(); ++i)
      for (Index& w : m.triangles[tris[i]])
        if (w == v) w = copy[fan[i]];
    out.push_back(std::move(copy));
  }
  return out;
}

}  // namespace stripweave
