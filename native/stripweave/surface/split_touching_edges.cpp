#include "stripweave/surface/split_touching_edges.h"

#include "stripweave/surface/mesh_topology.h"

#include <algorithm>
#include <map>
#include <unordered_map>

namespace stripweave {

namespace {

// The faces (and their triangles) that must give the edge up: see the header.
std::vector<Index> triangles_to_split(const std::vector<Index>& uses, const std::vector<Index>& face_of_triangle) {
  std::map<Index, std::vector<Index>> by_face;  // ordered: the first face is the lowest id
  for (Index t : uses) by_face[face_of_triangle[t]].push_back(t);
  const bool border = std::any_of(by_face.begin(), by_face.end(), [](const auto& g) { return g.second.size() == 1; });
  std::vector<Index> out;
  bool kept_inside = border;
  for (const auto& [face, ts] : by_face) {
    if (ts.size() == 1) continue;            // the edge is on this face's border
    if (!kept_inside) { kept_inside = true; continue; }
    out.insert(out.end(), ts.begin(), ts.end());
  }
  return out;
}

}  // namespace

Index split_touching_edges(TriangleMesh& mesh, std::vector<Index>& face_of_triangle) {
  std::unordered_map<std::uint64_t, std::vector<Index>> uses;
  for (Index t = 0; t < mesh.num_triangles(); ++t)
    for (int i = 0; i < 3; ++i) uses[pack_edge(edge_key(mesh.triangles[t][i], mesh.triangles[t][(i + 1) % 3]))].push_back(t);
  // Deterministic order: by edge key.
  std::vector<std::pair<std::uint64_t, std::vector<Index>>> fins;
  for (auto& [k, ts] : uses)
    if (ts.size() > 2) fins.emplace_back(k, std::move(ts));
  std::sort(fins.begin(), fins.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Index split = 0;
  for (const auto& [key, ts] : fins) {
    const Index u = static_cast<Index>(key >> 32), v = static_cast<Index>(key & 0xffffffffu);
    const std::vector<Index> cut = triangles_to_split(ts, face_of_triangle);
    if (cut.empty()) continue;
    std::map<Index, Index> midpoint_of_face;  // one new vertex per face giving the edge up
    for (Index t : cut) {
      const Index face = face_of_triangle[t];
      auto [it, fresh] = midpoint_of_face.emplace(face, mesh.num_vertices());
      if (fresh) mesh.positions.push_back(0.5 * (mesh.positions[u] + mesh.positions[v]));
      const Index m = it->second;
      Tri tri = mesh.triangles[t];
      // Rotate so that the edge is (tri[0], tri[1]) in the triangle's own order.
      while (!((tri[0] == u && tri[1] == v) || (tri[0] == v && tri[1] == u))) tri = {tri[1], tri[2], tri[0]};
      mesh.triangles[t] = {tri[0], m, tri[2]};
      mesh.triangles.push_back({m, tri[1], tri[2]});
      face_of_triangle.push_back(face);
    }
    ++split;
  }
  return split;
}

Index part_touching_faces(TriangleMesh& mesh, std::vector<Index>& face_of_triangle, std::vector<EdgeKey>& segments,
                          std::vector<Index>& corners) {
  const Index split = split_touching_edges(mesh, face_of_triangle);
  const std::vector<std::vector<Index>> copies = split_pinched_vertices(mesh, MeshTopology::build(mesh));
  if (copies.empty()) return split;
  std::unordered_map<Index, const std::vector<Index>*> copies_of;
  for (const auto& c : copies) copies_of[c.front()] = &c;
  auto copies_or_self = [&](Index v) {
    auto it = copies_of.find(v);
    return it == copies_of.end() ? std::vector<Index>{v} : *it->second;
  };
  std::unordered_map<std::uint64_t, char> mesh_edge;
  for (const Tri& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) mesh_edge[pack_edge(edge_key(t[i], t[(i + 1) % 3]))] = 1;
  for (EdgeKey& k : segments) {
    if (!copies_of.count(k[0]) && !copies_of.count(k[1])) continue;
    for (Index a : copies_or_self(k[0]))
      for (Index b : copies_or_self(k[1]))
        if (mesh_edge.count(pack_edge(edge_key(a, b)))) k = edge_key(a, b);
  }
  const size_t n = corners.size();
  for (size_t i = 0; i < n; ++i)
    if (copies_of.count(corners[i]))
      for (size_t c = 1; c < copies_of[corners[i]]->size(); ++c) corners.push_back((*copies_of[corners[i]])[c]);
  return split;
}

}  // namespace stripweave
