#include "stripweave/layout/cut_triangle.h"

namespace stripweave {

std::vector<Tri> cut_triangle(const Tri& f, const std::array<Index, 3>& mid) {
  const int splits = (mid[0] != kInvalid) + (mid[1] != kInvalid) + (mid[2] != kInvalid);
  if (splits == 0) return {f};
  if (splits == 3)
    return {Tri{f[0], mid[0], mid[2]}, Tri{mid[0], f[1], mid[1]}, Tri{mid[2], mid[1], f[2]},
            Tri{mid[0], mid[1], mid[2]}};
  if (splits == 1) {
    const int i = mid[0] != kInvalid ? 0 : mid[1] != kInvalid ? 1 : 2;
    const Index a = f[i], b = f[(i + 1) % 3], c = f[(i + 2) % 3];
    return {Tri{a, mid[i], c}, Tri{mid[i], b, c}};
  }
  // Two: sides i and i + 1 split, meeting at corner b = f[i + 1].
  const int i = mid[0] == kInvalid ? 1 : mid[1] == kInvalid ? 2 : 0;
  const Index a = f[i], b = f[(i + 1) % 3], c = f[(i + 2) % 3];
  const Index p = mid[i], q = mid[(i + 1) % 3];
  return {Tri{p, b, q}, Tri{a, p, q}, Tri{a, q, c}};
}

std::vector<Index> cut_triangles(TriangleMesh& mesh, const MeshTopology& topology, const std::vector<Index>& mid) {
  std::vector<Index> source;
  const Index nt = mesh.num_triangles();
  for (Index t = 0; t < nt; ++t) {
    const auto& te = topology.triangle_edges[t];
    const std::array<Index, 3> at{mid[te[0]], mid[te[1]], mid[te[2]]};
    if (at[0] == kInvalid && at[1] == kInvalid && at[2] == kInvalid) continue;
    const std::vector<Tri> pieces = cut_triangle(mesh.triangles[t], at);
    mesh.triangles[t] = pieces[0];
    for (size_t p = 1; p < pieces.size(); ++p) {
      mesh.triangles.push_back(pieces[p]);
      source.push_back(t);
    }
  }
  return source;
}

}  // namespace stripweave
