#include "stripweave/surfacing/fit_patch_network.h"

#include "stripweave/core/error.h"
#include "stripweave/core/parallel.h"
#include "stripweave/surface/creases.h"
#include "stripweave/surfacing/edge_curves.h"
#include "stripweave/surfacing/fit_deviation.h"
#include "stripweave/surfacing/patch_creases.h"
#include "stripweave/surfacing/patch_fit.h"
#include "stripweave/surfacing/patch_parameterization.h"
#include "stripweave/surfacing/patch_shell.h"
#include "stripweave/surfacing/sample_memo.h"
#include "stripweave/surfacing/source_projection.h"
#include "stripweave/surfacing/split_strip.h"
#include "stripweave/surfacing/symmetric_fit.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <numeric>
#include <sstream>

namespace stripweave {

namespace {

struct SideUse {
  Index patch = kInvalid;
  int side = 0;
  bool reversed = false;
};

// Union-find over network edges: the layout's strips.
struct Strips {
  std::vector<Index> parent;
  explicit Strips(Index n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  Index find(Index a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(Index a, Index b) { parent[find(a)] = find(b); }
};

std::string where(Index patch, int side) {
  std::ostringstream s;
  s << "side " << side << " of patch " << patch;
  return s.str();
}

template <typename T>
void sort_unique(std::vector<T>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// Orthogonal deviation of the samples from the fitted network: the own
// patch, and where the foot point lands on its border (the sample may lie
// beyond the smooth edge curve, on the neighbour's side of a zig-zag mesh
// edge path), the nearest of the patches sharing a vertex with it.
double distance_to_network(const std::vector<BSplinePatch>& patches, Index p, const std::vector<Index>& neighbours,
                           const Vec3& x, const Vec2& uv, double enough) {
  Vec2 foot;
  double d = distance_to_patch(patches[p], x, uv, &foot);
  const bool border = foot.x() <= 1e-9 || foot.x() >= 1 - 1e-9 || foot.y() <= 1e-9 || foot.y() >= 1 - 1e-9;
  if (!border || d <= enough) return d;
  for (Index q : neighbours) {
    const BSplinePatch& Q = patches[q];
    // Start from the nearest of a 5 x 5 grid of the neighbour.
    Vec2 start(0.5, 0.5);
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 4; ++i)
      for (int j = 0; j <= 4; ++j) {
        const double e = (Q.value(i / 4.0, j / 4.0) - x).squaredNorm();
        if (e < best) best = e, start = Vec2(i / 4.0, j / 4.0);
      }
    d = std::min(d, distance_to_patch(Q, x, start, nullptr));
    if (d <= enough) break;
  }
  return d;
}

void measure(const std::vector<BSplinePatch>& patches, Index p, const std::vector<Index>& neighbours,
             const PatchSamples& s, double enough, PatchFitFigures& fig) {
  const BSplinePatch& patch = patches[p];
  double worst = 0, sum2 = 0;
  for (size_t k = 0; k < s.points.size(); ++k) {
    const double d = distance_to_network(patches, p, neighbours, s.points[k], s.uv[k], enough);
    if (d > worst) worst = d, fig.worst_uv = s.uv[k];
    sum2 += d * d;
  }
  fig.fit_max_deviation = worst;
  fig.fit_rms_deviation = s.points.empty() ? 0 : std::sqrt(sum2 / s.points.size());
  fig.samples = static_cast<Index>(s.points.size());
  fig.nu = patch.nu, fig.nv = patch.nv;
}

// The reported figures: the two-sided deviation and the coverage
// (fit_deviation.h), overall and per patch; the tolerance is met when both
// directions are within it and the patches cover the source.
void report_deviation(const Surface& surface, const std::vector<BSplinePatch>& surfaces, const FitOptions& options,
                      FitReport& report) {
  const double tol = report.tolerance;
  FitDeviation& dev = report.deviation;
  dev = fit_deviation(surface, surfaces, tol, options.deviation);
  double uncreased_edges = 0;
  for (size_t p = 0; p < surfaces.size(); ++p) {
    PatchFitFigures& f = report.per_patch[p];
    const PatchDeviation& d = dev.per_patch[p];
    f.max_deviation = d.max_deviation();
    f.rms_deviation = std::max(d.rms_source_to_patch, d.rms_patch_to_source);
    if (f.creased()) continue;
    report.max_deviation_uncreased = std::max(report.max_deviation_uncreased, f.max_deviation);
    uncreased_edges = std::max(uncreased_edges, f.side_deviation);
  }
  report.max_deviation = std::max(dev.max_source_to_patches, dev.max_patches_to_source);
  report.rms_deviation = std::max(dev.rms_source_to_patches, dev.rms_patches_to_source);
  for (const auto& [name, ms] : dev.timings) report.timings.emplace_back("deviation_" + name, ms);
  report.tolerance_met = report.max_deviation <= tol && dev.coverage >= kCoverageMet;
  report.tolerance_met_uncreased = report.max_deviation_uncreased <= tol && uncreased_edges <= tol;
}

constexpr int kMaxRounds = 40;  // refinement rounds of one fit

double angle_deg(const Vec3& a, const Vec3& b) {
  if (a.isZero() || b.isZero()) return 0;
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

// Steps 1 to 5 (the header) on one network, without the shell. `memo`: the
// samples of the fits before (sample_memo.h).
FitResult fit_network(const Surface& surface, const PatchNetwork& network, const FitOptions& options,
                      SampleMemo& memo) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  FitResult result;
  FitReport& report = result.report;
  Stopwatch watch(report.timings);

  const Index nE = static_cast<Index>(network.edges.size());
  const Index nP = static_cast<Index>(network.patches.size());
  const Index nV = static_cast<Index>(network.vertices.size());
  if (nP == 0) throw InputError("the patch network has no patches");
  const double diag = network.bbox_diagonal > 0 ? network.bbox_diagonal : 1.0;
  const double tol = options.tolerance > 0 ? options.tolerance : options.relative_tolerance * diag;
  report.tolerance = tol;
  // Stages for the GUI's progress; Cancelled from a cancel() (FitOptions::progress).
  auto checkpoint = [&](const char* stage, double begin, double end) {
    if (options.progress) options.progress->stage(stage, begin, end);
  };
  auto check = [&]() {
    if (options.progress) options.progress->check();
  };
  checkpoint("parameterizing the patches", 0.0, 0.1);

  // --- the network's incidences and consistency ---------------------------
  for (Index e = 0; e < nE; ++e) {
    const NetworkEdge& E = network.edges[e];
    if (E.v0 < 0 || E.v0 >= nV || E.v1 < 0 || E.v1 >= nV)
      throw InputError("network edge " + std::to_string(e) + " names a vertex that does not exist");
    if (E.points.size() < 2) throw InputError("network edge " + std::to_string(e) + " has fewer than 2 points");
  }
  std::vector<std::vector<SideUse>> uses(nE);
  for (Index p = 0; p < nP; ++p)
    for (int s = 0; s < 4; ++s) {
      const Index e = network.patches[p].edges[s];
      if (e < 0 || e >= nE) throw InputError(where(p, s) + " names an edge that does not exist");
      uses[e].push_back({p, s, network.patches[p].reversed[s]});
      if (uses[e].size() > 2) throw InputError("network edge " + std::to_string(e) + " bounds more than two patch sides");
    }

  // Patches sharing a vertex (for the deviation near patch borders).
  std::vector<std::vector<Index>> vertex_patches(nV), neighbours(nP);
  std::vector<std::vector<Index>> patch_vertices(nP);
  for (Index p = 0; p < nP; ++p) {
    for (Index e : network.patches[p].edges)
      for (Index v : {network.edges[e].v0, network.edges[e].v1}) patch_vertices[p].push_back(v);
    sort_unique(patch_vertices[p]);
    for (Index v : patch_vertices[p]) vertex_patches[v].push_back(p);
  }
  for (Index p = 0; p < nP; ++p) {
    for (Index v : patch_vertices[p])
      for (Index q : vertex_patches[v])
        if (q != p) neighbours[p].push_back(q);
    sort_unique(neighbours[p]);
  }
  const double enough = 1e-2 * tol;  // a sample this close needs no search among the neighbours

  // Step 7: the layout's images under each symmetry.
  std::vector<NetworkPairing> pairings;
  const double symmetry_tol = options.symmetry_tolerance > 0 ? options.symmetry_tolerance : 1e-3 * diag;
  for (const Symmetry& psi : options.symmetries) {
    pairings.push_back(pair_network(network, psi, symmetry_tol));
    if (!pairings.back().paired && report.symmetry_problem.empty()) report.symmetry_problem = pairings.back().problem;
  }

  // --- 1. harmonic parameterization ----------------------------------------
  std::vector<PatchParameterization> param(nP);
  for (Index p = 0; p < nP; ++p) {
    try {
      param[p] = harmonic_square_map(network.patches[p]);
    } catch (const InputError& e) {
      throw InputError("patch " + std::to_string(p) + ": " + e.what());
    }
    for (int s = 0; s < 4; ++s) {
      const NetworkEdge& E = network.edges[network.patches[p].edges[s]];
      if (param[p].side_vertices[s].size() != E.points.size())
        throw InputError(where(p, s) + " has " + std::to_string(param[p].side_vertices[s].size()) +
                         " boundary points in the patch mesh but its edge polyline has " +
                         std::to_string(E.points.size()));
    }
  }
  watch.lap("parameterize");
  checkpoint("sampling the source", 0.1, 0.3);

  // --- 2. samples on the source --------------------------------------------
  const SourceProjector projector(surface, options.edge_snap * diag);
  // Faces around each patch-mesh vertex.
  std::vector<std::vector<std::vector<Index>>> vertex_faces(nP);
  std::vector<bool> has_faces(nP, false);
  for (Index p = 0; p < nP; ++p) {
    const NetworkPatch& P = network.patches[p];
    const TriangleMesh& m = P.mesh;
    has_faces[p] = projector.exact() && P.source_face.size() == m.triangles.size();
    auto& vf = vertex_faces[p];
    vf.assign(m.num_vertices(), {});
    if (has_faces[p]) {
      for (Index t = 0; t < m.num_triangles(); ++t)
        for (Index v : m.triangles[t]) vf[v].push_back(P.source_face[t]);
      for (auto& f : vf) sort_unique(f);
    }
  }

  const int density = std::max(1, options.edge_density);
  std::vector<EdgeSamples> edge_samples(nE);
  std::vector<bool> edge_smoothed(nE, false);
  for (Index e = 0; e < nE; ++e) {
    const NetworkEdge& E = network.edges[e];
    // Faces along the polyline, from every patch side on this edge.
    std::vector<std::vector<Index>> point_faces;
    if (projector.exact()) {
      point_faces.assign(E.points.size(), {});
      for (const SideUse& u : uses[e]) {
        const auto& verts = param[u.patch].side_vertices[u.side];
        const size_t n = verts.size();
        for (size_t k = 0; k < n; ++k) {
          // Side k runs counter-clockwise in the patch; the edge from v0.
          const size_t i = u.reversed ? n - 1 - k : k;
          const auto& f = vertex_faces[u.patch][verts[k]];
          point_faces[i].insert(point_faces[i].end(), f.begin(), f.end());
        }
      }
      for (auto& f : point_faces) sort_unique(f);
    }
    std::vector<Vec3> polyline = E.points;
    polyline.front() = network.vertices[E.v0];
    polyline.back() = network.vertices[E.v1];
    edge_smoothed[e] = !E.sharp && !E.boundary && uses[e].size() == 2 && options.edge_smoothing > 0;
    const double smooth = edge_smoothed[e] ? options.edge_smoothing : 0.0;
    // Each edge from no warm start: its samples depend on it alone (sample_memo.h).
    MemoKey key;
    key.add(polyline).add(E.sharp).add(density).add(smooth);
    for (const auto& f : point_faces) key.add(f);
    if (const EdgeSamples* known = memo.edges.find(key)) {
      edge_samples[e] = *known;
      continue;
    }
    projector.forget_warm_starts();
    edge_samples[e] = sample_edge(polyline, point_faces, E.sharp, projector, density, smooth);
    memo.edges.store(key, edge_samples[e]);
  }

  // Smoothed edges: the patch meshes' boundary vertices move onto their
  // edge's smoothed samples (the same points for both patches of a seam),
  // the two rings inside relax (Laplacian, projected back onto the source)
  // to take up the shift, and the harmonic map is redone. Otherwise the map
  // would pin the zig-zag mesh path to the square's side while the edge
  // curve runs smooth, up to half a mesh edge away: samples near the border
  // would disagree with the edge curves across the seam by that much, which
  // the fit can only answer with ripples.
  std::vector<TriangleMesh> moved(nP);
  for (Index p = 0; p < nP; ++p) {
    const NetworkPatch& P = network.patches[p];
    bool any = false;
    for (int s = 0; s < 4; ++s) any = any || edge_smoothed[P.edges[s]];
    if (!any) continue;
    TriangleMesh m = P.mesh;
    const Index nv = m.num_vertices();
    MemoKey key;
    key.add(m.positions).add(m.triangles).add(P.source_face).add(P.corners).add(P.reversed);
    for (int s = 0; s < 4; ++s) key.add(edge_smoothed[P.edges[s]] ? edge_samples[P.edges[s]].points : std::vector<Vec3>{});
    const std::vector<Vec3>* known = memo.moved.find(key);
    std::vector<int> ring(nv, -1);  // 0: boundary, 1, 2: rings inside
    for (int s = 0; s < 4; ++s) {
      const Index e = P.edges[s];
      const auto& verts = param[p].side_vertices[s];
      const size_t n = verts.size();
      for (size_t k = 0; k < n; ++k) {
        ring[verts[k]] = 0;
        if (!edge_smoothed[e] || k == 0 || k + 1 == n) continue;
        const size_t i = P.reversed[s] ? n - 1 - k : k;
        m.positions[verts[k]] = edge_samples[e].points[i * density];
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
        next[v] = projector.on_faces(vertex_faces[p][v], c / double(nbr[v].size()));
      }
      m.positions = std::move(next);
    }
    if (known) m.positions = *known;
    else memo.moved.store(key, m.positions);
    NetworkPatch copy;
    copy.edges = P.edges, copy.reversed = P.reversed, copy.corners = P.corners;
    copy.mesh = m;
    try {
      param[p] = harmonic_square_map(copy);
    } catch (const InputError& e) {
      throw InputError("patch " + std::to_string(p) + ": " + e.what());
    }
    moved[p] = std::move(m);
  }

  // Each patch's samples are projected in breadth-first order over its
  // mesh (a vertex, then the triangles and edges it opens), so consecutive
  // projections onto a face are neighbours: the local Newton from the
  // previous foot point (BrepSource::project_to_face with `near`) then
  // converges, where the index order sent it across the face and back to
  // the global search (a grid of distances per call; seconds per patch on
  // B-spline faces). The samples keep their slots: vertices, then one
  // centroid per triangle, then one midpoint per mesh edge.
  //
  // Patches are sampled side by side on the cores the process may use, each
  // thread through a projector of its own (the B-rep's caches are per
  // thread), and each patch from no warm start, so that the samples do not
  // depend on which thread sampled which patch before. A mesh source (no
  // B-rep) is sampled on one thread: its locator is shared.
  // A patch sampled by an earlier fit of this call (a patch no split
  // touched) takes those samples (sample_memo.h).
  std::vector<PatchSamples> samples(nP);
  std::vector<MemoKey> sample_keys(nP);
  std::vector<Index> todo;
  for (Index p = 0; p < nP; ++p) {
    const TriangleMesh& m = moved[p].num_vertices() ? moved[p] : network.patches[p].mesh;
    sample_keys[p].add(m.positions).add(m.triangles).add(param[p].uv).add(bool(has_faces[p]));
    if (has_faces[p]) sample_keys[p].add(network.patches[p].source_face);
    if (const PatchSamples* known = memo.patches.find(sample_keys[p])) samples[p] = *known;
    else todo.push_back(p);
  }
  const Index nTodo = static_cast<Index>(todo.size());
  const unsigned sample_workers = projector.exact() ? parallel_workers(nTodo) : 1;
  std::vector<std::unique_ptr<SourceProjector>> worker_projectors(sample_workers);
  if (projector.exact())
    for (auto& w : worker_projectors) w = projector.thread_copy();
  parallel_for_workers(nTodo, [&](Index k, unsigned worker) {
    check();
    const Index p = todo[k];
    const SourceProjector& own = worker_projectors[worker] ? *worker_projectors[worker] : projector;
    own.forget_warm_starts();
    const NetworkPatch& P = network.patches[p];
    const TriangleMesh& m = moved[p].num_vertices() ? moved[p] : P.mesh;
    const auto& vf = vertex_faces[p];
    const auto& uv = param[p].uv;
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

    PatchSamples& S = samples[p];
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
          const std::vector<Index> faces = has_faces[p] ? std::vector<Index>{P.source_face[t]} : std::vector<Index>{};
          sample(nv + t, faces, (uv[f[0]] + uv[f[1]] + uv[f[2]]) / 3,
                 (m.positions[f[0]] + m.positions[f[1]] + m.positions[f[2]]) / 3);
        }
        // Edge midpoints: faces of either end (a midpoint lies in one of the
        // two triangles along the edge, whose faces are among the ends').
        for (Index e : vertex_edges[v]) {
          const EdgeKey& k = edges[e];
          std::vector<Index> faces;
          if (has_faces[p]) {
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
  }, sample_workers);
  for (Index p : todo) memo.patches.store(sample_keys[p], samples[p]);
  watch.lap("sample");
  checkpoint("fitting B-spline patches", 0.3, 0.6);

  // --- 3. strips and adaptive refinement -----------------------------------
  Strips strips(nE);
  for (const NetworkPatch& P : network.patches) {
    strips.unite(P.edges[0], P.edges[2]);
    strips.unite(P.edges[1], P.edges[3]);
  }
  // A strip and its images share their span count (step 7).
  for (const NetworkPairing& pairing : pairings)
    if (pairing.paired)
      for (Index e = 0; e < nE; ++e) strips.unite(e, pairing.edge_image[e]);
  std::vector<Index> strip_of(nE);
  for (Index e = 0; e < nE; ++e) strip_of[e] = strips.find(e);
  std::vector<int> spans(nE, std::max(1, options.initial_spans));  // per strip root

  result.edge_curves.assign(nE, {});
  result.surfaces.assign(nP, {});
  report.per_patch.assign(nP, {});
  std::vector<double> edge_dev(nE, 0.0);
  std::vector<bool> edge_dirty(nE, true), patch_dirty(nP, true);

  auto set_boundary = [&](Index p) {
    const NetworkPatch& P = network.patches[p];
    BSplinePatch& B = result.surfaces[p];
    B.nu = spans[strip_of[P.edges[0]]];
    B.nv = spans[strip_of[P.edges[1]]];
    B.control.assign(size_t(B.rows()) * B.cols(), Vec3::Zero());
    for (int s = 0; s < 4; ++s) {
      const BSplineCurve3& c = result.edge_curves[P.edges[s]];
      const int N = side_size(B, s);
      for (int k = 0; k < N; ++k) {
        const auto ij = side_control(B, s, k, 0);
        B.P(ij[0], ij[1]) = c.control[P.reversed[s] ? N - 1 - k : k];
      }
    }
  };

  // Parameter correction: each sample's (u, v) becomes its foot point on
  // the current fit, and samples whose foot point lies on the patch border
  // (beyond the smooth edge curve, the neighbour's side of a zig-zag mesh
  // edge path) leave the fit. The harmonic map puts the patch mesh's
  // zig-zag boundary on the square's sides, so near the border it is off by
  // up to half a mesh edge across the seam: fitted as they are, these
  // samples bend the patch to reconcile parameters that disagree with the
  // edge curves.
  std::vector<PatchSamples> fit_samples = samples;
  auto correct_parameters = [&](Index p) {
    const BSplinePatch& B = result.surfaces[p];
    PatchSamples& S = samples[p];
    PatchSamples& F = fit_samples[p];
    F.uv.clear(), F.points.clear();
    for (size_t k = 0; k < S.points.size(); ++k) {
      Vec2 foot;
      distance_to_patch(B, S.points[k], S.uv[k], &foot);
      S.uv[k] = foot;
      const bool border = foot.x() <= 1e-9 || foot.x() >= 1 - 1e-9 || foot.y() <= 1e-9 || foot.y() >= 1 - 1e-9;
      if (!border) F.uv.push_back(foot), F.points.push_back(S.points[k]);
    }
  };

  // Smooth vertices (every edge there a smooth seam between two patches):
  // the surface normal for the edge curves' end tangents (edge_curves.h):
  // the source's exact normal where there is a B-rep, else the
  // area-weighted mean of the patch-mesh triangles around the corners
  // there. Zero elsewhere: at a sharp or boundary vertex the patches need
  // not share a normal.
  std::vector<Vec3> vertex_normal(nV, Vec3::Zero());
  if (options.vertex_tangent_planes) {
    std::vector<bool> smooth(nV, true);
    for (Index e = 0; e < nE; ++e) {
      const NetworkEdge& E = network.edges[e];
      const bool seam = uses[e].size() == 2 && !E.sharp && !E.boundary;
      smooth[E.v0] = smooth[E.v0] && seam;
      smooth[E.v1] = smooth[E.v1] && seam;
    }
    std::vector<std::vector<Index>> faces_at(nV);
    for (Index p = 0; p < nP; ++p) {
      const NetworkPatch& P = network.patches[p];
      for (int s = 0; s < 4; ++s) {
        const NetworkEdge& E = network.edges[P.edges[s]];
        const Index v = P.reversed[s] ? E.v1 : E.v0;
        if (!smooth[v]) continue;
        const auto& f = vertex_faces[p][P.corners[s]];
        faces_at[v].insert(faces_at[v].end(), f.begin(), f.end());
        for (Index t = 0; t < P.mesh.num_triangles(); ++t)
          for (Index c : P.mesh.triangles[t])
            if (c == P.corners[s]) vertex_normal[v] += triangle_normal_area2(P.mesh, t);
      }
    }
    for (Index v = 0; v < nV; ++v) {
      if (vertex_normal[v].norm() <= 0) continue;
      sort_unique(faces_at[v]);
      const Vec3 exact = projector.normal_on_faces(faces_at[v], network.vertices[v]);
      vertex_normal[v] = exact.norm() > 0 ? exact : Vec3(vertex_normal[v].normalized());
    }
  }

  auto fit_round = [&]() {
    for (Index e = 0; e < nE; ++e)
      if (edge_dirty[e]) {
        const NetworkEdge& E = network.edges[e];
        result.edge_curves[e] = fit_edge_curve(edge_samples[e], network.vertices[E.v0], network.vertices[E.v1],
                                               spans[strip_of[e]], options.smoothing, vertex_normal[E.v0],
                                               vertex_normal[E.v1]);
        edge_dev[e] = edge_curve_deviation(result.edge_curves[e], edge_samples[e]);
      }
    std::vector<Index> which;
    for (Index p = 0; p < nP; ++p)
      if (patch_dirty[p]) set_boundary(p), which.push_back(p);
    if (!which.empty()) {
      fit_patch_interiors(result.surfaces, fit_samples, which, {}, options.smoothing, 0);
      for (int c = 0; c < options.parameter_corrections; ++c) {
        for (Index p : which) correct_parameters(p);
        fit_patch_interiors(result.surfaces, fit_samples, which, {}, options.smoothing, 0);
      }
    }
    // Each patch's samples against the network: independent, side by side.
    parallel_for(static_cast<Index>(which.size()), [&](Index k) {
      measure(result.surfaces, which[k], neighbours[which[k]], samples[which[k]], enough, report.per_patch[which[k]]);
    });
    std::fill(edge_dirty.begin(), edge_dirty.end(), false);
    std::fill(patch_dirty.begin(), patch_dirty.end(), false);
  };

  // Raise the span count of the strips through everything above tolerance.
  auto refine = [&]() {
    std::vector<int> want(nE, 0);
    auto ask = [&](Index e, double err) {
      const Index r = strip_of[e];
      const int n = spans[r];
      if (n >= options.max_spans) return;
      const double factor = std::pow(std::max(err / tol, 1.0), 0.25) * 1.15;
      const int m = std::min(options.max_spans, std::max(n + 1, static_cast<int>(std::ceil(n * factor))));
      want[r] = std::max(want[r], m);
    };
    for (Index e = 0; e < nE; ++e)
      if (edge_dev[e] > tol && !uses[e].empty()) ask(e, edge_dev[e]);
    for (Index p = 0; p < nP; ++p)
      if (report.per_patch[p].fit_max_deviation > tol)
        for (int s = 0; s < 2; ++s) ask(network.patches[p].edges[s], report.per_patch[p].fit_max_deviation);
    bool changed = false;
    for (Index r = 0; r < nE; ++r)
      if (want[r] > spans[r]) spans[r] = want[r], changed = true;
    if (!changed) return false;
    for (Index e = 0; e < nE; ++e) edge_dirty[e] = spans[strip_of[e]] != result.edge_curves[e].spans;
    for (Index p = 0; p < nP; ++p)
      for (int s = 0; s < 4; ++s) patch_dirty[p] = patch_dirty[p] || edge_dirty[network.patches[p].edges[s]];
    return true;
  };

  // Smooth seams (two patches, not sharp): the C1 coupling.
  std::vector<Seam> seams;
  std::vector<Index> seam_edge;
  for (Index e = 0; e < nE; ++e) {
    const NetworkEdge& E = network.edges[e];
    if (uses[e].size() == 1 || E.boundary) {
      ++report.boundary_edges;
      continue;
    }
    if (uses[e].size() != 2) continue;
    if (E.sharp) {
      ++report.sharp_seams;
      continue;
    }
    ++report.smooth_seams;
    Seam s;
    s.a = uses[e][0].patch, s.side_a = uses[e][0].side;
    s.b = uses[e][1].patch, s.side_b = uses[e][1].side;
    s.b_reversed = uses[e][0].reversed != uses[e][1].reversed;
    if (s.a == s.b) continue;  // a patch glued to itself: leave it C0
    seams.push_back(s);
    seam_edge.push_back(e);
  }

  // Largest normal-angle jump over the middle of the smooth seams.
  auto seam_angle = [&](const std::vector<BSplinePatch>& surfaces) {
    double worst = 0;
    for (const Seam& sm : seams)
      for (int k = 0; k <= 20; ++k) {
        const double t = options.seam_from + (options.seam_to - options.seam_from) * k / 20.0;
        const Vec2 ua = side_uv(sm.side_a, t), ub = side_uv(sm.side_b, sm.b_reversed ? 1 - t : t);
        worst = std::max(worst, angle_deg(surfaces[sm.a].normal(ua.x(), ua.y()), surfaces[sm.b].normal(ub.x(), ub.y())));
      }
    return worst;
  };

  for (int outer = 0; outer < 3; ++outer) {
    do {
      check();
      fit_round();
      ++report.rounds;
    } while (report.rounds < kMaxRounds && refine());
    if (seams.empty() || options.seam_weight <= 0) break;
    // 4. Tangent continuity across smooth seams.
    const std::vector<BSplinePatch> uncoupled = result.surfaces;
    const std::vector<PatchFitFigures> uncoupled_fig = report.per_patch;
    if (options.seam_mode == 1) {
      for (Seam& s : seams) s.alpha = seam_speed_ratio(result.surfaces, s);
      fit_patch_interiors(result.surfaces, fit_samples, {}, seams, options.smoothing, options.seam_weight);
    } else {
      for (int round = 0; round < std::max(1, options.tangent_rounds); ++round) {
        std::vector<ControlTarget> targets;
        for (const Seam& sm : seams) {
          const BSplinePatch &A = result.surfaces[sm.a], &B = result.surfaces[sm.b];
          const int N = side_size(A, sm.side_a);
          if (side_size(B, sm.side_b) != N) continue;
          const int n = N - 3;  // spans along the seam
          auto knot = [&](int j) { return std::clamp(double(j - 3) / n, 0.0, 1.0); };
          for (int m = 1; m <= N - 2; ++m) {
            const int mb = sm.b_reversed ? N - 1 - m : m;
            const double t = (knot(m + 1) + knot(m + 2) + knot(m + 3)) / 3;  // Greville
            const Vec2 ua = side_uv(sm.side_a, t), ub = side_uv(sm.side_b, sm.b_reversed ? 1 - t : t);
            const Vec3 na = A.normal(ua.x(), ua.y()), nb = B.normal(ub.x(), ub.y());
            Vec3 nm = na + (na.dot(nb) >= 0 ? nb : Vec3(-nb));
            if (nm.norm() <= 1e-12) continue;
            nm.normalize();
            const auto q = side_control(A, sm.side_a, m, 0);
            const Vec3 Q = A.P(q[0], q[1]);
            const auto ca = side_control(A, sm.side_a, m, 1);
            const auto cb = side_control(B, sm.side_b, mb, 1);
            const Vec3 a = A.P(ca[0], ca[1]), b = B.P(cb[0], cb[1]);
            targets.push_back({sm.a, ca[0], ca[1], Vec3(a - (a - Q).dot(nm) * nm)});
            targets.push_back({sm.b, cb[0], cb[1], Vec3(b - (b - Q).dot(nm) * nm)});
          }
        }
        fit_patch_interiors(result.surfaces, fit_samples, {}, {}, options.smoothing, 0, targets, options.seam_weight);
      }
    }
    parallel_for(nP, [&](Index p) {
      check();
      measure(result.surfaces, p, neighbours[p], samples[p], enough, report.per_patch[p]);
    });
    // If the coupling pushed a patch over tolerance, refine and go again,
    // from the uncoupled fits: a round refits only the patches whose spans
    // changed, and the others must not keep their coupled interiors: a
    // network half coupled, half not, meets at the largest seam angles of
    // all (the lofted part of tests/test_refit.py with two belts, at 20,000
    // triangles: 7.1 degrees over the middle of its seams and 3.9 at its
    // regular ones, where all uncoupled meet at 0.9 and all coupled at 0.2;
    // now 0.14 and 1.2).
    if (report.rounds < kMaxRounds && outer < 2 && refine()) {
      for (Index p = 0; p < nP; ++p)
        if (!patch_dirty[p]) result.surfaces[p] = uncoupled[p], report.per_patch[p] = uncoupled_fig[p];
      continue;
    }
    // Refinement is exhausted: tolerance before tangent continuity.
    for (Index p = 0; p < nP; ++p)
      if (report.per_patch[p].fit_max_deviation > tol &&
          uncoupled_fig[p].fit_max_deviation < report.per_patch[p].fit_max_deviation) {
        result.surfaces[p] = uncoupled[p];
        report.per_patch[p] = uncoupled_fig[p];
        ++report.uncoupled_patches;
      }
    // The seam condition is a means to tangent continuity, not an end: where
    // the uncoupled fits already meet better at the smooth seams (an
    // accurate fit of a smooth source is nearly G1 by itself, and the
    // condition, being stronger than G1, can cost more than it gives), keep
    // them.
    if (seam_angle(uncoupled) < seam_angle(result.surfaces)) {
      result.surfaces = uncoupled;
      report.per_patch = uncoupled_fig;
      report.uncoupled_patches = nP;
    }
    break;
  }
  watch.lap("fit");
  checkpoint("reporting", 0.6, 0.62);

  // --- 7. symmetry -----------------------------------------------------------
  if (!pairings.empty()) {
    report.symmetric = std::all_of(pairings.begin(), pairings.end(), [](const NetworkPairing& p) { return p.paired; });
    FitNets nets{std::move(result.edge_curves), std::move(result.surfaces)};
    report.symmetry_error_fit = symmetry_error(nets, network, options.symmetries, pairings);
    report.symmetry_error = symmetrize_fit(nets, network, options.symmetries, pairings, diag);
    result.edge_curves = std::move(nets.edges);
    result.surfaces = std::move(nets.patches);
    for (Index e = 0; e < nE; ++e) edge_dev[e] = edge_curve_deviation(result.edge_curves[e], edge_samples[e]);
    parallel_for(nP, [&](Index p) {
      measure(result.surfaces, p, neighbours[p], samples[p], enough, report.per_patch[p]);
    });
    watch.lap("symmetry");
  }

  // --- 5. report ------------------------------------------------------------
  // Per patch: its edge curves, the part's creases under it (the surface's
  // one crease set) and where the fit turns its back on the source
  // (patch_creases.h).
  const SegmentLocator creases = crease_locator(surface);
  const CreaseTest crease_test{options.crease_angle_deg, 1e-6 * diag};
  for (Index p = 0; p < nP; ++p) {
    const NetworkPatch& P = network.patches[p];
    PatchFitFigures& f = report.per_patch[p];
    for (Index e : P.edges) f.side_deviation = std::max(f.side_deviation, edge_dev[e]);
    const PatchCreases c = patch_creases(P.mesh, creases, crease_test);
    f.crease_deg = c.max_dihedral_deg, f.crease_edges = c.crease_edges, f.crease_length = c.crease_length;
    f.over_crease = c.crease_length > kCreasedPatchLength * diag;
    // Centroid samples follow the vertex samples, one per triangle.
    const TriangleMesh& m = moved[p].num_vertices() ? moved[p] : P.mesh;
    const Index nv = m.num_vertices();
    double flipped = 0, area = 0;
    for (Index t = 0; t < m.num_triangles() && nv + t < Index(samples[p].uv.size()); ++t) {
      const Vec3 n = triangle_normal_area2(m, t);
      const Vec2& uv = samples[p].uv[nv + t];
      area += n.norm();
      if (result.surfaces[p].normal(uv.x(), uv.y()).dot(n) < 0) flipped += n.norm();
    }
    f.flipped_fraction = area > 0 ? flipped / area : 0;
    report.creased_patches += f.creased();
    report.folded_patches += f.folded();
  }

  // The refinement's own measure (at the fit samples), for reference.
  double sum2 = 0;
  Index count = 0;
  for (const PatchFitFigures& f : report.per_patch) {
    report.fit_max_deviation = std::max(report.fit_max_deviation, f.fit_max_deviation);
    sum2 += f.fit_rms_deviation * f.fit_rms_deviation * f.samples;
    count += f.samples;
  }
  report.fit_rms_deviation = count ? std::sqrt(sum2 / count) : 0;
  // Edges no patch uses (their patches were left out of the network) say
  // nothing about the fitted shell.
  for (Index e = 0; e < nE; ++e)
    if (!uses[e].empty()) report.max_edge_deviation = std::max(report.max_edge_deviation, edge_dev[e]);
  watch.lap("report");
  checkpoint("measuring the deviation both ways", 0.62, 0.9);
  // The fit's own samples and per-thread projectors are done with: freed before the
  // deviation builds its tessellations and trees, the peak of the surfacing stage.
  std::vector<PatchSamples>().swap(samples);
  std::vector<PatchSamples>().swap(fit_samples);
  std::vector<EdgeSamples>().swap(edge_samples);
  worker_projectors.clear();
  report_deviation(surface, result.surfaces, options, report);
  watch.lap("deviation");
  checkpoint("measuring the seams", 0.9, 0.93);

  // Regular vertices: exactly 4 smooth seams meet there.
  std::vector<Index> valence(nV, 0);
  std::vector<bool> regular(nV, true);
  for (Index e = 0; e < nE; ++e)
    for (Index v : {network.edges[e].v0, network.edges[e].v1}) {
      ++valence[v];
      if (network.edges[e].sharp || network.edges[e].boundary || uses[e].size() != 2) regular[v] = false;
    }
  constexpr int kSeamSamples = 41;
  for (Index e = 0; e < nE; ++e) {
    if (uses[e].size() != 2) continue;
    const SideUse &a = uses[e][0], &b = uses[e][1];
    const BSplinePatch &A = result.surfaces[a.patch], &B = result.surfaces[b.patch];
    for (int k = 0; k < kSeamSamples; ++k) {
      const double t = double(k) / (kSeamSamples - 1);  // along the edge, from v0
      const Vec2 ua = side_uv(a.side, a.reversed ? 1 - t : t);
      const Vec2 ub = side_uv(b.side, b.reversed ? 1 - t : t);
      report.max_seam_gap =
          std::max(report.max_seam_gap, (A.value(ua.x(), ua.y()) - B.value(ub.x(), ub.y())).norm());
      if (k == 0 || k == kSeamSamples - 1) continue;
      const double angle = angle_deg(A.normal(ua.x(), ua.y()), B.normal(ub.x(), ub.y()));
      if (network.edges[e].sharp || network.edges[e].boundary) {
        report.max_sharp_angle_deg = std::max(report.max_sharp_angle_deg, angle);
        continue;
      }
      report.max_seam_angle_deg_full = std::max(report.max_seam_angle_deg_full, angle);
      if (t >= options.seam_from - 1e-12 && t <= options.seam_to + 1e-12)
        report.max_seam_angle_deg = std::max(report.max_seam_angle_deg, angle);
      const NetworkEdge& E = network.edges[e];
      if (regular[E.v0] && valence[E.v0] == 4 && regular[E.v1] && valence[E.v1] == 4)
        report.max_seam_angle_deg_regular = std::max(report.max_seam_angle_deg_regular, angle);
    }
  }
  watch.lap("measure");
  report.time_s = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

double polyline_length(const std::vector<Vec3>& points) {
  double length = 0;
  for (size_t k = 1; k < points.size(); ++k) length += (points[k] - points[k - 1]).norm();
  return length;
}

// How far a patch misses: the reported two-sided deviation, or the
// refinement's own measure at its fit samples.
double patch_miss(const PatchFitFigures& f) { return std::max(f.max_deviation, f.fit_max_deviation); }

// A patch whose strip is to be split (step 6), and why.
struct SplitChoice {
  StripCut cut;
  double deviation = 0;
  std::string reason;
};

// The patches above tolerance whose spans ran out (or whose fit ran out of
// rounds), worst first; a patch over a crease is left alone (a layout
// problem: the strips should run along the crease, and no split mends
// that). The cut refines the saturated direction, or, both saturated, the
// one whose spans are longer on the part; it runs through the worst
// sample, kept within the middle half of the patch so that both pieces
// get a fair share of it.
std::vector<SplitChoice> split_choices(const PatchNetwork& net, const FitReport& report, const FitOptions& options) {
  std::vector<SplitChoice> out;
  const double tol = report.tolerance;
  const bool rounds_out = report.rounds >= kMaxRounds;
  for (Index p = 0; p < Index(net.patches.size()); ++p) {
    const PatchFitFigures& f = report.per_patch[p];
    const double deviation = patch_miss(f);
    const bool saturated[2] = {f.nu >= options.max_spans, f.nv >= options.max_spans};
    // A patch whose own fit samples all lie within tolerance misses between
    // them or across a seam: the cut through its worst sample would be placed
    // blind, and every such trial costs a full refit (the corpus: 8 of 8
    // splits undone on a casting, the fit's peak memory doubled).
    if (f.fit_max_deviation <= tol) continue;
    if (deviation <= tol || f.creased() || !(saturated[0] || saturated[1] || rounds_out)) continue;
    const NetworkPatch& P = net.patches[p];
    auto length = [&](int s) { return polyline_length(net.edges[P.edges[s]].points); };
    const double span_u = (length(0) + length(2)) / (2.0 * std::max(f.nu, 1));
    const double span_v = (length(1) + length(3)) / (2.0 * std::max(f.nv, 1));
    const int d = saturated[0] != saturated[1] ? (saturated[0] ? 0 : 1) : (span_u >= span_v ? 0 : 1);
    std::ostringstream why;
    why << "accuracy: " << deviation << " > tolerance " << tol << " at " << f.nu << " x " << f.nv << " spans ("
        << (rounds_out ? "the refinement ran out of rounds" : "max_spans " + std::to_string(options.max_spans))
        << ")";
    out.push_back({{p, d, std::clamp(f.worst_uv[d], 0.25, 0.75)}, deviation, why.str()});
  }
  std::stable_sort(out.begin(), out.end(), [](const SplitChoice& a, const SplitChoice& b) {
    return a.deviation > b.deviation;
  });
  return out;
}

// The splits of one round, applied to a copy of the network.
struct SplitRound {
  std::shared_ptr<PatchNetwork> net;
  std::vector<Index> layout;         // per patch, the input network's patch
  std::vector<SplitChoice> choices;  // the cuts made, one per split
  std::vector<PatchSplit> splits;
  std::vector<bool> touched;         // per patch: in a split strip (a piece of it)
  std::vector<Index> base;           // per patch, the patch of the round's base network it is (a piece of)
};

// One split per strip: a patch a split crossed is fitted again before it is
// judged again.
SplitRound apply_splits(const PatchNetwork& base, const std::vector<Index>& layout,
                        const std::vector<SplitChoice>& choices, int round, Index budget) {
  SplitRound r{std::make_shared<PatchNetwork>(base), layout, {}, {}, std::vector<bool>(base.patches.size(), false),
               std::vector<Index>(base.patches.size())};
  std::iota(r.base.begin(), r.base.end(), 0);
  for (const SplitChoice& c : choices) {
    if (r.touched[c.cut.patch] || Index(r.splits.size()) >= budget) continue;
    const StripSplit s = split_strip(*r.net, c.cut);
    if (!s.done) continue;
    r.touched.resize(r.net->patches.size(), true);
    for (Index q : s.patches) {  // new_patches, in order
      r.touched[q] = true;
      r.layout.push_back(r.layout[q]);
      r.base.push_back(r.base[q]);
    }
    PatchSplit p;
    p.patch = c.cut.patch, p.layout_patch = r.layout[c.cut.patch];
    p.direction = c.cut.direction, p.at = c.cut.at;
    p.deviation_before = c.deviation, p.reason = c.reason;
    p.strip = s.patches, p.new_patches = s.new_patches, p.closed_strip = s.closed, p.round = round;
    r.choices.push_back(c);
    r.splits.push_back(std::move(p));
  }
  return r;
}

// How far a patch itself lies from the source: its own samples both ways
// at the fit, its surface against the source; not the source nearest to it,
// which a hole or a neighbour elsewhere may decide.
double patch_own_miss(const FitReport& r, Index p) {
  return std::max(r.per_patch[p].fit_max_deviation, r.deviation.per_patch[p].max_patch_to_source);
}

// Whether a split helped: the patch it was made for came closer to the
// source (the larger of its two pieces against it before), and no other
// patch of its strip came to lie further from it than both the tolerance
// and itself before. Each patch by its own distance (patch_own_miss): a
// hole next to it is no business of the split. (And not the strip's
// largest: another patch of the strip, over a crease, may hold it whatever
// the split does.)
// `base`: per patch after, the patch before it is (a piece of): a strip may
// run through pieces of another split of the round.
bool strip_helped(const FitReport& before, const FitReport& after, const std::vector<Index>& base,
                  const PatchSplit& s) {
  for (size_t k = 0; k < s.strip.size(); ++k) {
    const Index q = s.strip[k], n = s.new_patches[k], b = base[q];
    const double is = std::max(patch_own_miss(after, q), patch_own_miss(after, n)), was = patch_own_miss(before, b);
    if (q == s.patch ? is >= was : is > std::max(was, before.tolerance)) return false;
  }
  return true;
}

// The network's largest patch_own_miss.
double network_own_miss(const FitReport& r) {
  double worst = 0;
  for (Index p = 0; p < Index(r.per_patch.size()); ++p) worst = std::max(worst, patch_own_miss(r, p));
  return worst;
}

// A round is kept when its refit meets the tolerance, or every split of it
// helped without raising the network's largest (own) deviation or folding
// more patches.
bool round_helped(const FitReport& before, const FitReport& after, const SplitRound& r) {
  if (after.tolerance_met) return true;
  for (const PatchSplit& s : r.splits)
    if (!strip_helped(before, after, r.base, s)) return false;
  return network_own_miss(after) <= network_own_miss(before) && after.folded_patches <= before.folded_patches;
}

// Step 6: split and refit while patches miss the tolerance at their most
// spans. The splits of a round that did not help (an error along a seam,
// which every piece keeps) are undone and the rest refitted; a round that does not help is undone whole and the splitting
// stops: a miss no split mends costs a refit or two, never a worse fit.
// `layout`: per patch of the fitted network, the input network's patch.
void split_and_refit(const Surface& surface, const PatchNetwork& network, const FitOptions& options,
                     FitResult& result, std::vector<Index>& layout, SampleMemo& memo) {
  std::shared_ptr<PatchNetwork> net;  // the split network, null until a round is kept
  std::vector<PatchSplit> kept, rejected;
  double other_fits_ms = 0;
  for (int round = 1; round <= options.split_rounds && Index(kept.size()) < options.max_splits; ++round) {
    const PatchNetwork& base = net ? *net : network;
    const Index budget = options.max_splits - Index(kept.size());
    SplitRound trial = apply_splits(base, layout, split_choices(base, result.report, options), round, budget);
    if (trial.splits.empty()) break;
    FitResult refit = fit_network(surface, *trial.net, options, memo);
    std::vector<SplitChoice> good;
    for (size_t k = 0; k < trial.splits.size(); ++k) {
      if (strip_helped(result.report, refit.report, trial.base, trial.splits[k])) good.push_back(trial.choices[k]);
      else rejected.push_back(trial.splits[k]);
    }
    if (!good.empty() && good.size() < trial.splits.size()) {
      other_fits_ms += 1e3 * refit.report.time_s;
      trial = apply_splits(base, layout, good, round, budget);
      refit = fit_network(surface, *trial.net, options, memo);
    }
    if (good.empty() || !round_helped(result.report, refit.report, trial)) {
      other_fits_ms += 1e3 * refit.report.time_s;
      if (!good.empty()) rejected.insert(rejected.end(), trial.splits.begin(), trial.splits.end());
      break;
    }
    other_fits_ms += 1e3 * result.report.time_s;
    result = std::move(refit);
    net = std::move(trial.net);
    layout = std::move(trial.layout);
    kept.insert(kept.end(), trial.splits.begin(), trial.splits.end());
    if (result.report.tolerance_met) break;
  }
  result.report.splits = std::move(kept);
  result.report.rejected_splits = std::move(rejected);
  result.network = net;
  if (other_fits_ms > 0) result.report.timings.emplace_back("other_fits", other_fits_ms);
}

}  // namespace

FitResult fit_patch_network(const Surface& surface, const PatchNetwork& network, const FitOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  SampleMemo memo;
  FitResult result = fit_network(surface, network, options, memo);
  std::vector<Index> layout(network.patches.size());
  std::iota(layout.begin(), layout.end(), 0);
  if (options.split_patches && !result.report.tolerance_met)
    split_and_refit(surface, network, options, result, layout, memo);
  FitReport& report = result.report;
  for (size_t p = 0; p < report.per_patch.size(); ++p) report.per_patch[p].layout_patch = layout[p];

  if (options.build_shell) {
    if (options.progress) options.progress->stage("sewing the shell", 0.93, 1.0);
    Stopwatch watch(report.timings);
    const double diag = network.bbox_diagonal > 0 ? network.bbox_diagonal : 1.0;
    ShellFigures fig;
    result.shell = sew_patch_shell(result.surfaces, 1e-6 * diag, &fig);
    report.faces = fig.faces, report.shells = fig.shells, report.free_edges = fig.free_edges;
    report.valid_shell = fig.valid, report.closed = fig.closed, report.solids = fig.solids;
    report.volume = fig.volume, report.shell_tolerance = fig.max_tolerance;
    watch.lap("shell");
  }
  report.time_s = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

namespace {

// The colour of a patch whose deviation is `ratio` times the tolerance, as the
// deviation picture draws it (preview.py's deviation_colour): green at 0,
// yellow at the tolerance, red at twice it and beyond, linear in between.
Vec3 deviation_colour(double ratio) {
  const Vec3 green(0.15, 0.65, 0.3), yellow(0.98, 0.85, 0.2), red(0.9, 0.15, 0.1);
  const double r = std::clamp(std::isfinite(ratio) ? ratio : 2.0, 0.0, 2.0);
  return r <= 1 ? Vec3((1 - r) * green + r * yellow) : Vec3((2 - r) * yellow + (r - 1) * red);
}

}  // namespace

Index write_step(const FitResult& result, const std::string& path) {
  std::vector<Vec3> colours;
  const double tolerance = result.report.tolerance;
  for (const PatchFitFigures& p : result.report.per_patch)
    colours.push_back(deviation_colour(tolerance > 0 ? p.max_deviation / tolerance : 0.0));
  if (result.shell) return write_step(*result.shell, path, colours);
  BoundingBox box;
  for (const BSplinePatch& p : result.surfaces)
    for (const Vec3& c : p.control) box.add(c);
  const auto shell = sew_patch_shell(result.surfaces, 1e-6 * std::max(box.diagonal(), 1e-9), nullptr);
  return write_step(*shell, path, colours);
}

}  // namespace stripweave
