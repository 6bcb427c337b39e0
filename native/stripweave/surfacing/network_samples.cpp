#include "stripweave/surfacing/network_samples.h"

#include "stripweave/core/error.h"
#include "stripweave/core/parallel.h"
#include "stripweave/core/sort_unique.h"

#include <algorithm>
#include <memory>

namespace stripweave {

namespace {

// Per patch, whether its mesh knows the source face of each triangle (a
// B-rep source), and then per mesh vertex the faces around it.
void source_faces_at_vertices(const PatchNetwork& network, const SourceProjector& projector, NetworkSamples& out,
                              std::vector<bool>& has_faces) {
  const Index nP = static_cast<Index>(network.patches.size());
  out.vertex_faces.assign(nP, {});
  has_faces.assign(nP, false);
  for (Index p = 0; p < nP; ++p) {
    const NetworkPatch& P = network.patches[p];
    const TriangleMesh& m = P.mesh;
    has_faces[p] = projector.exact() && P.source_face.size() == m.triangles.size();
    auto& vf = out.vertex_faces[p];
    vf.assign(m.num_vertices(), {});
    if (!has_faces[p]) continue;
    for (Index t = 0; t < m.num_triangles(); ++t)
      for (Index v : m.triangles[t]) vf[v].push_back(P.source_face[t]);
    for (auto& f : vf) sort_unique(f);
  }
}

// Per polyline point of edge e, the source faces around it in every patch
// side along the edge.
std::vector<std::vector<Index>> edge_point_faces(const PatchNetwork& network, const NetworkTopology& topology,
                                                 const std::vector<PatchParameterization>& param,
                                                 const NetworkSamples& out, Index e) {
  std::vector<std::vector<Index>> point_faces(network.edges[e].points.size());
  for (const SideUse& u : topology.uses[e]) {
    const auto& verts = param[u.patch].side_vertices[u.side];
    const size_t n = verts.size();
    for (size_t k = 0; k < n; ++k) {
      // Side k runs counter-clockwise in the patch; the edge from v0.
      const size_t i = u.reversed ? n - 1 - k : k;
      const auto& f = out.vertex_faces[u.patch][verts[k]];
      point_faces[i].insert(point_faces[i].end(), f.begin(), f.end());
    }
  }
  for (auto& f : point_faces) sort_unique(f);
  return point_faces;
}

void sample_edges(const PatchNetwork& network, const NetworkTopology& topology,
                  const std::vector<PatchParameterization>& param, const SourceProjector& projector,
                  const FitOptions& options, SampleMemo& memo, NetworkSamples& out) {
  const Index nE = static_cast<Index>(network.edges.size());
  const int density = std::max(1, options.edge_density);
  out.edges.assign(nE, {});
  out.edge_smoothed.assign(nE, false);
  for (Index e = 0; e < nE; ++e) {
    const NetworkEdge& E = network.edges[e];
    const std::vector<std::vector<Index>> point_faces =
        projector.exact() ? edge_point_faces(network, topology, param, out, e) : std::vector<std::vector<Index>>{};
    std::vector<Vec3> polyline = E.points;
    polyline.front() = network.vertices[E.v0];
    polyline.back() = network.vertices[E.v1];
    out.edge_smoothed[e] = !E.sharp && !E.boundary && topology.uses[e].size() == 2 && options.edge_smoothing > 0;
    const double smooth = out.edge_smoothed[e] ? options.edge_smoothing : 0.0;
    // Each edge from no warm start: its samples depend on it alone (sample_memo.h).
    MemoKey key;
    key.add(polyline).add(E.sharp).add(density).add(smooth);
    for (const auto& f : point_faces) key.add(f);
    if (const EdgeSamples* known = memo.edges.find(key)) {
      out.edges[e] = *known;
      continue;
    }
    projector.forget_warm_starts();
    out.edges[e] = sample_edge(polyline, point_faces, E.sharp, projector, density, smooth);
    memo.edges.store(key, out.edges[e]);
  }
}

// Patch p's mesh with its border on the smoothed samples of its edges and
// the two rings inside relaxed (Laplacian, projected back onto the source)
// to take up the shift; its square map redone on it.
void relax_smoothed_border(const PatchNetwork& network, Index p, const SourceProjector& projector,
                           const FitOptions& options, SampleMemo& memo, PatchParameterization& param,
                           NetworkSamples& out) {
  const NetworkPatch& P = network.patches[p];
  const int density = std::max(1, options.edge_density);
  TriangleMesh m = P.mesh;
  const Index nv = m.num_vertices();
  MemoKey key;
  key.add(m.positions).add(m.triangles).add(P.source_face).add(P.corners).add(P.reversed);
  for (int s = 0; s < 4; ++s)
    key.add(out.edge_smoothed[P.edges[s]] ? out.edges[P.edges[s]].points : std::vector<Vec3>{});
  const std::vector<Vec3>* known = memo.moved.find(key);
  std::vector<int> ring(nv, -1);  // 0: boundary, 1, 2: rings inside
  for (int s = 0; s < 4; ++s) {
    const Index e = P.edges[s];
    const auto& verts = param.side_vertices[s];
    const size_t n = verts.size();
    for (size_t k = 0; k < n; ++k) {
      ring[verts[k]] = 0;
      if (!out.edge_smoothed[e] || k == 0 || k + 1 == n) continue;
      const size_t i = P.reversed[s] ? n - 1 - k : k;
      m.positions[verts[k]] = out.edges[e].points[i * density];
    }
  }
  std::vector<std::vector<Index>> nbr(nv);
  for (const Tri& f : m.triangles)
    for (int k = 0; k < 3; ++k) nbr[f[k]].push_back(f[(k + 1) % 3]), nbr[f[k]].push_back(f[(k + 2) % 3]);
  for (auto& l : nbr) sort_unique(l);
  projector.forget_warm_starts();  // each patch from no warm start (sample_memo.h)
  for (int r = 1; r <= 2 && !known; ++r)
    for (Index v = 0; v < nv; ++v)
      if (ring[v] < 0)
        for (Index w : nbr[v])
          if (ring[w] == r - 1) {
            ring[v] = r;
            break;
          }
  for (int it = 0; it < 4 && !known; ++it) {
    std::vector<Vec3> next = m.positions;
    for (Index v = 0; v < nv; ++v) {
      if (ring[v] != 1 && ring[v] != 2) continue;
      Vec3 c = Vec3::Zero();
      for (Index w : nbr[v]) c += m.positions[w];
      next[v] = projector.on_faces(out.vertex_faces[p][v], c / double(nbr[v].size()));
    }
    m.positions = std::move(next);
  }
  if (known) m.positions = *known;
  else memo.moved.store(key, m.positions);
  NetworkPatch copy = P;  // the patch, its border moved
  copy.mesh.positions = m.positions;
  try {
    param = square_map(copy);
  } catch (const InputError& e) {
    throw InputError("patch " + std::to_string(p) + ": " + e.what());
  }
  out.moved[p] = std::move(m);
}

// One patch's samples, in breadth-first order over its mesh (a vertex, then
// the triangles and edges it opens), so that consecutive projections onto a
// face are neighbours: the local Newton from the previous foot point
// (BrepSource::project_to_face with `near`) then converges, where the index
// order sent it across the face and back to the global search (a grid of
// distances per call; seconds per patch on B-spline faces). The samples
// keep their slots: vertices, then one centroid per triangle, then one
// midpoint per mesh edge.
PatchSamples sample_patch(const NetworkPatch& P, const TriangleMesh& m, const PatchParameterization& param,
                          const std::vector<std::vector<Index>>& vf, bool has_faces, const SourceProjector& own) {
  const auto& uv = param.uv;
  const Index nv = m.num_vertices(), nt = m.num_triangles();
  std::vector<std::vector<Index>> vertex_triangles(nv);
  for (Index t = 0; t < nt; ++t)
    for (Index v : m.triangles[t]) vertex_triangles[v].push_back(t);
  std::vector<EdgeKey> edges;
  for (const Tri& f : m.triangles)
    for (int k = 0; k < 3; ++k) edges.push_back(edge_key(f[k], f[(k + 1) % 3]));
  sort_unique(edges);
  std::vector<std::vector<Index>> vertex_edges(nv);
  for (Index e = 0; e < Index(edges.size()); ++e) vertex_edges[edges[e][0]].push_back(e), vertex_edges[edges[e][1]].push_back(e);

  PatchSamples S;
  const size_t total = size_t(nv) + nt + edges.size();
  S.uv.assign(total, Vec2::Zero());
  S.points.assign(total, Vec3::Zero());
  std::vector<bool> done(total, false), queued(nv, false);
  auto sample = [&](size_t slot, const std::vector<Index>& faces, const Vec2& at, const Vec3& x) {
    if (done[slot]) return;
    done[slot] = true;
    S.uv[slot] = at;
    S.points[slot] = own.on_faces(faces, x);
  };
  std::vector<Index> queue;
  for (Index seed = 0; seed < nv; ++seed) {
    if (queued[seed]) continue;
    queued[seed] = true;
    queue.assign(1, seed);
    for (size_t head = 0; head < queue.size(); ++head) {
      const Index v = queue[head];
      sample(v, vf[v], uv[v], m.positions[v]);
      for (Index t : vertex_triangles[v]) {
        const Tri& f = m.triangles[t];
        const std::vector<Index> faces = has_faces ? std::vector<Index>{P.source_face[t]} : std::vector<Index>{};
        sample(nv + t, faces, (uv[f[0]] + uv[f[1]] + uv[f[2]]) / 3,
               (m.positions[f[0]] + m.positions[f[1]] + m.positions[f[2]]) / 3);
      }
      // Edge midpoints: faces of either end (a midpoint lies in one of the
      // two triangles along the edge, whose faces are among the ends').
      for (Index e : vertex_edges[v]) {
        const EdgeKey& k = edges[e];
        std::vector<Index> faces;
        if (has_faces) {
          faces = vf[k[0]];
          faces.insert(faces.end(), vf[k[1]].begin(), vf[k[1]].end());
          sort_unique(faces);
        }
        sample(size_t(nv) + nt + e, faces, (uv[k[0]] + uv[k[1]]) / 2, (m.positions[k[0]] + m.positions[k[1]]) / 2);
        const Index w = k[0] == v ? k[1] : k[0];
        if (!queued[w]) queued[w] = true, queue.push_back(w);
      }
    }
  }
  return S;
}

// Every patch's samples, side by side on the cores the process may use, each
// thread through a projector of its own, each patch from no warm start. A
// mesh source (no B-rep) is sampled on one thread: its locator is shared.
void sample_patches(const PatchNetwork& network, const std::vector<PatchParameterization>& param,
                    const std::vector<bool>& has_faces, const SourceProjector& projector, const FitOptions& options,
                    SampleMemo& memo, NetworkSamples& out) {
  const Index nP = static_cast<Index>(network.patches.size());
  out.patches.assign(nP, {});
  std::vector<MemoKey> keys(nP);
  std::vector<Index> todo;
  for (Index p = 0; p < nP; ++p) {
    const TriangleMesh& m = out.mesh(network, p);
    keys[p].add(m.positions).add(m.triangles).add(param[p].uv).add(bool(has_faces[p]));
    if (has_faces[p]) keys[p].add(network.patches[p].source_face);
    if (const PatchSamples* known = memo.patches.find(keys[p])) out.patches[p] = *known;
    else todo.push_back(p);
  }
  const Index nTodo = static_cast<Index>(todo.size());
  const unsigned workers = projector.exact() ? parallel_workers(nTodo) : 1;
  std::vector<std::unique_ptr<SourceProjector>> own(workers);
  if (projector.exact())
    for (auto& w : own) w = projector.thread_copy();
  parallel_for_workers(nTodo, [&](Index k, unsigned worker) {
    if (options.progress) options.progress->check();
    const Index p = todo[k];
    const SourceProjector& proj = own[worker] ? *own[worker] : projector;
    proj.forget_warm_starts();
    out.patches[p] = sample_patch(network.patches[p], out.mesh(network, p), param[p], out.vertex_faces[p],
                                  has_faces[p], proj);
  }, workers);
  for (Index p : todo) memo.patches.store(keys[p], out.patches[p]);
}

}  // namespace

NetworkSamples sample_network(const PatchNetwork& network, const NetworkTopology& topology,
                              std::vector<PatchParameterization>& param, const SourceProjector& projector,
                              const FitOptions& options, SampleMemo& memo) {
  const Index nP = static_cast<Index>(network.patches.size());
  NetworkSamples out;
  std::vector<bool> has_faces;
  source_faces_at_vertices(network, projector, out, has_faces);
  sample_edges(network, topology, param, projector, options, memo, out);
  out.moved.assign(nP, {});
  for (Index p = 0; p < nP; ++p) {
    const NetworkPatch& P = network.patches[p];
    bool any = false;
    for (int s = 0; s < 4; ++s) any = any || out.edge_smoothed[P.edges[s]];
    if (any) relax_smoothed_border(network, p, projector, options, memo, param[p], out);
  }
  sample_patches(network, param, has_faces, projector, options, memo, out);
  return out;
}

std::vector<Vec3> smooth_vertex_normals(const PatchNetwork& network, const NetworkTopology& topology,
                                        const NetworkSamples& samples, const SourceProjector& projector) {
  const Index nE = static_cast<Index>(network.edges.size());
  const Index nV = static_cast<Index>(network.vertices.size());
  std::vector<Vec3> normal(nV, Vec3::Zero());
  std::vector<bool> smooth(nV, true);
  for (Index e = 0; e < nE; ++e) {
    const NetworkEdge& E = network.edges[e];
    const bool seam = topology.uses[e].size() == 2 && !E.sharp && !E.boundary;
    smooth[E.v0] = smooth[E.v0] && seam;
    smooth[E.v1] = smooth[E.v1] && seam;
  }
  std::vector<std::vector<Index>> faces_at(nV);
  for (Index p = 0; p < Index(network.patches.size()); ++p) {
    const NetworkPatch& P = network.patches[p];
    for (int s = 0; s < 4; ++s) {
      const NetworkEdge& E = network.edges[P.edges[s]];
      const Index v = P.reversed[s] ? E.v1 : E.v0;
      if (!smooth[v]) continue;
      const auto& f = samples.vertex_faces[p][P.corners[s]];
      faces_at[v].insert(faces_at[v].end(), f.begin(), f.end());
      for (Index t = 0; t < P.mesh.num_triangles(); ++t)
        for (Index c : P.mesh.triangles[t])
          if (c == P.corners[s]) normal[v] += triangle_normal_area2(P.mesh, t);
    }
  }
  for (Index v = 0; v < nV; ++v) {
    if (normal[v].norm() <= 0) continue;
    sort_unique(faces_at[v]);
    const Vec3 exact = projector.normal_on_faces(faces_at[v], network.vertices[v]);
    normal[v] = exact.norm() > 0 ? exact : Vec3(normal[v].normalized());
  }
  return normal;
}

}  // namespace stripweave
