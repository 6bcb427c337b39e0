#include "stripweave/surfacing/fit_deviation.h"

#include "stripweave/cgal/surface_locator.h"
#include "stripweave/core/parallel.h"
#include "stripweave/occt/brep_source.h"
#include "stripweave/surfacing/patch_fit.h"
#include "stripweave/surfacing/patch_grid.h"
#include "stripweave/surfacing/source_projection.h"
#include "stripweave/surfacing/source_samples.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>

namespace stripweave {

namespace {

constexpr Index kBlock = 512;  // samples per parallel work item

Index blocks_of(size_t n) { return static_cast<Index>((n + kBlock - 1) / kBlock); }

// The solver mesh's mean edge length, in model units, kept so that the
// source gets at most max_samples samples (about 2.3 per spacing^2 of area).
double default_spacing(const Surface& surface, Index max_samples) {
  const TriangleMesh& m = surface.mesh;
  const double s = surface.similarity.scale;
  double length = 0, area = 0;
  for (const EdgeKey& e : surface.topology.edges) length += (m.positions[e[1]] - m.positions[e[0]]).norm();
  for (const Tri& t : m.triangles)
    area += 0.5 * (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).norm();
  const double h = surface.topology.edges.empty() ? 0.01 : length / surface.topology.edges.size();
  return s * std::max(h, std::sqrt(2.3 * area / std::max<Index>(max_samples, 1)));
}

// All patch grids as one mesh: per vertex its (u, v), per triangle its patch.
struct PatchMesh {
  TriangleMesh mesh;
  std::vector<Vec2> uv;
  std::vector<Index> patch;
  double max_chord = 0;
};

using GridCells = std::array<int, 2>;  // {nu, nv}

// The triangles of the grids, each cut to at most cap x cap cells.
size_t triangles_under_cap(const std::vector<GridCells>& cells, int cap) {
  size_t n = 0;
  for (const GridCells& c : cells) n += 2 * size_t(std::min(c[0], cap)) * size_t(std::min(c[1], cap));
  return n;
}

// Within max_triangles: the largest per-direction cell count c for which the
// grids, each cut to at most c x c cells, fit; every grid is cut to it.
// Patches that need fewer cells keep theirs: the coarsening falls on the
// patches that ripple most, whose deviation is farthest above any tolerance.
void cap_cells(std::vector<GridCells>& cells, size_t max_triangles) {
  if (triangles_under_cap(cells, kMaxGridSamples) <= max_triangles) return;
  int lo = 1, hi = kMaxGridSamples;  // triangles_under_cap(lo) fits (or lo = 1), hi does not
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    (triangles_under_cap(cells, mid) <= max_triangles ? lo : hi) = mid;
  }
  for (GridCells& c : cells) c = {std::min(c[0], lo), std::min(c[1], lo)};
}

// The tessellation for nearest-point queries: per patch a grid only as fine
// as the chordal error asks (2 per span at least), within max_triangles
// (cap_cells). The grids are kept as made while their total stays within the
// cap (then the cap does not bind and they are the tessellation); past it
// they are dropped as made and made again at their capped size, so at most
// the cap's worth of grids is ever held (a network far off its source asks
// for ten times the cap: 0088's 86 patches, 580 MB of grids when all were
// held and then cut).
PatchMesh patch_tessellation(const std::vector<BSplinePatch>& patches, double chord, Index max_triangles) {
  const Index nP = static_cast<Index>(patches.size());
  const size_t cap = static_cast<size_t>(std::max<Index>(max_triangles, 2 * nP));
  std::vector<GridCells> cells(nP);
  std::vector<PatchGrid> made(nP);
  std::atomic<size_t> total{0};
  parallel_for(nP, [&](Index p) {
    PatchGrid g = patch_grid(patches[p], 0.0, chord, 2);
    cells[p] = {g.nu, g.nv};
    if ((total += g.triangles.size()) <= cap) made[p] = std::move(g);
  });
  const bool capped = total > cap;
  if (capped) {
    std::vector<PatchGrid>().swap(made);
    cap_cells(cells, cap);
  }
  std::vector<size_t> first_vertex(nP + 1, 0), first_triangle(nP + 1, 0);
  for (Index p = 0; p < nP; ++p) {
    first_vertex[p + 1] = first_vertex[p] + size_t(cells[p][0] + 1) * size_t(cells[p][1] + 1);
    first_triangle[p + 1] = first_triangle[p] + 2 * size_t(cells[p][0]) * size_t(cells[p][1]);
  }
  PatchMesh out;
  out.mesh.positions.resize(first_vertex[nP]);
  out.uv.resize(first_vertex[nP]);
  out.mesh.triangles.resize(first_triangle[nP]);
  out.patch.resize(first_triangle[nP]);
  std::vector<double> chords(nP, 0.0);
  // Each patch's grid is written into its own range and dropped.
  parallel_for(nP, [&](Index p) {
    PatchGrid g = capped ? patch_grid_of_size(patches[p], cells[p][0], cells[p][1]) : std::move(made[p]);
    const Index base = static_cast<Index>(first_vertex[p]);
    std::copy(g.points.begin(), g.points.end(), out.mesh.positions.begin() + first_vertex[p]);
    std::copy(g.uv.begin(), g.uv.end(), out.uv.begin() + first_vertex[p]);
    for (size_t t = 0; t < g.triangles.size(); ++t) {
      const Tri& f = g.triangles[t];
      out.mesh.triangles[first_triangle[p] + t] = {base + f[0], base + f[1], base + f[2]};
    }
    std::fill(out.patch.begin() + first_triangle[p], out.patch.begin() + first_triangle[p + 1], p);
    chords[p] = g.max_chord;
  });
  for (double c : chords) out.max_chord = std::max(out.max_chord, c);
  return out;
}

template <typename T>
T interpolate(const std::vector<T>& at_vertex, const Tri& t, const Vec3& b) {
  return b.x() * at_vertex[t[0]] + b.y() * at_vertex[t[1]] + b.z() * at_vertex[t[2]];
}

// Per solver triangle, the uncovered share of the source samples on it; a
// triangle without samples takes the mean of its neighbours' (a few rounds).
std::vector<double> triangle_uncovered(const Surface& surface, const SourceSamples& S,
                                       const std::vector<double>& distance, double tolerance) {
  const Index nT = surface.mesh.num_triangles();
  std::vector<double> total(nT, 0.0), uncovered(nT, 0.0), result(nT, 0.0);
  if (nT == 0) return result;
  const SurfaceLocator locator(surface.mesh);
  std::vector<Index> where(S.points.size());
  parallel_for(blocks_of(S.points.size()), [&](Index b) {
    const size_t end = std::min(S.points.size(), size_t(b + 1) * kBlock);
    SurfacePoint3 hint;  // each block from no hint: the answers do not depend on the threads
    for (size_t k = size_t(b) * kBlock; k < end; ++k) {
      hint = locator.closest(surface.similarity.to_normalized(S.points[k]), hint);
      where[k] = hint.triangle;
    }
  });
  for (size_t k = 0; k < where.size(); ++k) {
    total[where[k]] += S.area[k];
    if (distance[k] > tolerance) uncovered[where[k]] += S.area[k];
  }
  std::vector<bool> known(nT);
  for (Index t = 0; t < nT; ++t) {
    known[t] = total[t] > 0;
    if (known[t]) result[t] = uncovered[t] / total[t];
  }
  const MeshTopology& topo = surface.topology;
  if (Index(topo.triangle_edges.size()) != nT) return result;
  for (int round = 0; round < 8; ++round) {
    std::vector<bool> next = known;
    bool missing = false;
    for (Index t = 0; t < nT; ++t) {
      if (known[t]) continue;
      double sum = 0;
      int n = 0;
      for (Index e : topo.triangle_edges[t])
        for (Index u : topo.edge_triangles[e])
          if (u != kInvalid && u != t && known[u]) sum += result[u], ++n;
      if (n) result[t] = sum / n, next[t] = true;
      else missing = true;
    }
    known = std::move(next);
    if (!missing) break;
  }
  return result;
}

}  // namespace

namespace {

// What both directions share: the source samples and the options as used.
struct Setup {
  SourceSamples S;
  const BrepSource* brep = nullptr;
  double h = 0, chord = 0, eps_source = 0;
};

Setup setup(const Surface& surface, double tolerance, const DeviationOptions& options, FitDeviation& out,
            Stopwatch& watch) {
  Setup u;
  u.h = options.spacing > 0 ? options.spacing : default_spacing(surface, options.max_source_samples);
  u.chord = options.chord > 0 ? options.chord : tolerance / 10;
  out.spacing = u.h;
  u.S = sample_source(surface, u.h, u.chord);
  watch.lap("source_samples");
  u.brep = surface.brep && !u.S.face.empty() ? surface.brep.get() : nullptr;
  u.eps_source = u.brep ? std::max(1.5 * u.S.max_chord, 2 * u.chord) : 0.0;
  out.source_chord = u.S.max_chord;
  out.unmeshed_faces = u.S.unmeshed_faces;
  return u;
}

// Source -> patches: per source sample its distance to the nearest patch and
// that patch; the patch tessellation's figures and measurement_error. The
// tessellation and its tree live in here only: the patch samples are made
// after they are gone, so that the two largest parts of the measurement never
// sit in memory together.
void source_to_patches(const Setup& u, const std::vector<BSplinePatch>& patches, const DeviationOptions& options,
                       std::vector<double>& ds, std::vector<Index>& owner, FitDeviation& out, Stopwatch& watch) {
  const Index nP = static_cast<Index>(patches.size());
  const size_t nS = u.S.points.size();
  ds.assign(nS, 0.0);
  owner.assign(nS, 0);
  const PatchMesh P = patch_tessellation(patches, u.chord, options.max_patch_triangles);
  watch.lap("patch_tessellation");
  out.patch_chord = P.max_chord;
  out.patch_triangles = P.mesh.num_triangles();
  // Chordal bounds of both tessellations (see the header).
  out.measurement_error = 2 * std::max(1.5 * P.max_chord, u.eps_source);
  if (nP == 0) return;
  const SurfaceLocator locator(P.mesh, false);  // every query but a block's first has a hint
  watch.lap("patch_tree");
  parallel_for(blocks_of(nS), [&](Index b) {
    const size_t end = std::min(nS, size_t(b + 1) * kBlock);
    SurfacePoint3 c;
    for (size_t k = size_t(b) * kBlock; k < end; ++k) {
      c = locator.closest(u.S.points[k], c);
      const Tri& t = P.mesh.triangles[c.triangle];
      const Index p = P.patch[c.triangle];
      ds[k] = distance_to_patch(patches[p], u.S.points[k], interpolate(P.uv, t, c.barycentric));
      owner[k] = p;
    }
  });
  watch.lap("source_to_patches");
}

// Patches -> source, in two passes: every patch at half the samples per
// span, then at the full density around every sample within 0.7 of the
// patch's largest (at half density a bump of the deviation peaking between
// samples shows at least cos(pi / 4) = 0.71 of its peak at one of them, so
// no bump that could top the largest is left out): each patch's maximum as
// if sampled at the full density, at a fraction of the cost. Fills the
// per-patch and overall patches -> source figures and patch_samples.
void patches_to_source(const Surface& surface, const Setup& u, const std::vector<BSplinePatch>& patches,
                       double tolerance, const DeviationOptions& options, FitDeviation& out, Stopwatch& watch) {
  const Index nP = static_cast<Index>(patches.size());
  const SourceSamples& S = u.S;
  const BrepSource* brep = u.brep;
  std::vector<PatchGrid> grids(nP);
  const int per_span = std::max(1, options.samples_per_span / 2);
  parallel_for(nP, [&](Index p) { grids[p] = patch_sample_grid(patches[p], u.h, per_span); });
  watch.lap("patch_samples");
  const SurfaceLocator source_locator(S.mesh, false);  // queries in patch order, hinted
  std::vector<std::shared_ptr<BrepSource>> copies(parallel_workers(Index(1) << 20));
  if (brep)
    for (auto& c : copies) c = brep->thread_copy();
  // A second look, for a patch sample whose foot on the face of its nearest
  // source triangle lies past half the tolerance: the nearest point of the
  // whole part within its faces' trims (SourceProjector::on_faces over every
  // face, nearest boxes first; no warm start, so the answer does not depend
  // on the thread). The source tessellation can leave a sliver of a face
  // uncovered (the shipped handle: a sample 0.008 from one face, whose
  // tessellation there lay 0.14 away, was reported at 0.133 from the
  // neighbour face, 1.4 tolerances, and the fit "missed"). Every answer is
  // a point of the part, so the figure is never below the true distance.
  std::vector<Index> every_face;
  if (brep)
    for (Index f = 0; f < brep->num_faces(); ++f) every_face.push_back(f);
  // Only with a B-rep (a mesh source's projector would build its own tree).
  const auto whole_part = brep ? std::make_unique<SourceProjector>(surface, 0.0) : nullptr;
  std::vector<std::unique_ptr<SourceProjector>> second_looks(copies.size());
  auto to_source = [&](const std::vector<Vec3>& points) {
    std::vector<double> d(points.size(), 0.0);
    const Index nb = blocks_of(points.size());
    parallel_for_workers(nb, [&](Index b, unsigned worker) {
      const size_t end = std::min(points.size(), size_t(b + 1) * kBlock);
      SurfacePoint3 c;
      for (size_t k = size_t(b) * kBlock; k < end; ++k) {
        const Vec3& x = points[k];
        c = source_locator.closest(x, c);
        if (!brep) {
          d[k] = c.distance;
          continue;
        }
        Vec2 uv = interpolate(S.uv, S.mesh.triangles[c.triangle], c.barycentric);
        double foot;
        copies[worker]->foot_on_face(S.face[c.triangle], x, uv, &foot);
        if (foot > 0.5 * tolerance) {
          if (!second_looks[worker]) second_looks[worker] = whole_part->thread_copy();
          foot = std::min(foot, (second_looks[worker]->on_faces(every_face, x) - x).norm());
        }
        d[k] = foot;
      }
    }, static_cast<unsigned>(copies.size()));
    return d;
  };
  std::vector<size_t> first(nP + 1, 0);
  for (Index p = 0; p < nP; ++p) first[p + 1] = first[p] + grids[p].points.size();
  const size_t nG = first[nP];
  std::vector<Vec3> nodes;
  nodes.reserve(nG);
  for (const PatchGrid& g : grids) nodes.insert(nodes.end(), g.points.begin(), g.points.end());
  const std::vector<double> dp = to_source(nodes);
  std::vector<Vec3> extra;
  std::vector<Index> extra_patch;
  for (Index p = 0; p < nP; ++p) {
    const PatchGrid& g = grids[p];
    const double largest = *std::max_element(dp.begin() + first[p], dp.begin() + first[p + 1]);
    for (size_t k = 0; k < g.points.size(); ++k) {
      if (dp[first[p] + k] < 0.7 * largest || largest <= 0) continue;
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b) {
          if (a == 0 && b == 0) continue;
          const Vec2 uv = (g.uv[k] + Vec2(0.5 * a / g.nu, 0.5 * b / g.nv)).cwiseMax(0.0).cwiseMin(1.0);
          extra.push_back(patches[p].value(uv.x(), uv.y()));
          extra_patch.push_back(p);
        }
    }
  }
  const std::vector<double> de = to_source(extra);
  watch.lap("patches_to_source");
  // Figures, summed in sample order.
  double s2_patches = 0, w_patches = 0;
  for (size_t k = 0; k < extra.size(); ++k) {
    PatchDeviation& f = out.per_patch[extra_patch[k]];
    f.max_patch_to_source = std::max(f.max_patch_to_source, de[k]);
  }
  for (Index p = 0; p < nP; ++p) {
    PatchDeviation& f = out.per_patch[p];
    double sum2 = 0, weight = 0;
    const PatchGrid& g = grids[p];
    for (size_t k = 0; k < g.points.size(); ++k) {
      const double d = dp[first[p] + k];
      f.max_patch_to_source = std::max(f.max_patch_to_source, d);
      sum2 += g.weight[k] * d * d, weight += g.weight[k];
    }
    f.patch_samples = static_cast<Index>(g.points.size());
    f.rms_patch_to_source = weight > 0 ? std::sqrt(sum2 / weight) : 0.0;
    f.patch_samples += static_cast<Index>(std::count(extra_patch.begin(), extra_patch.end(), p));
    out.max_patches_to_source = std::max(out.max_patches_to_source, f.max_patch_to_source);
    s2_patches += sum2, w_patches += weight;
  }
  out.rms_patches_to_source = w_patches > 0 ? std::sqrt(s2_patches / w_patches) : 0.0;
  out.patch_samples = static_cast<Index>(nG + extra.size());
}

// The source -> patches figures (summed in sample order), the coverage and
// the uncovered share per solver triangle.
void source_figures(const Surface& surface, const Setup& u, const std::vector<double>& ds,
                    const std::vector<Index>& owner, double tolerance, FitDeviation& out, Stopwatch& watch) {
  const SourceSamples& S = u.S;
  const size_t nS = S.points.size();
  double s2_source = 0, w_source = 0;
  std::vector<double> s2(out.per_patch.size(), 0.0);
  for (size_t k = 0; k < nS; ++k) {
    const double a = S.area[k], d = ds[k];
    PatchDeviation& f = out.per_patch[owner[k]];
    f.max_source_to_patch = std::max(f.max_source_to_patch, d);
    f.source_area += a, ++f.source_samples;
    s2[owner[k]] += a * d * d;
    out.max_source_to_patches = std::max(out.max_source_to_patches, d);
    s2_source += a * d * d, w_source += a;
    if (d > tolerance) out.uncovered_area += a;
  }
  for (size_t p = 0; p < out.per_patch.size(); ++p) {
    PatchDeviation& f = out.per_patch[p];
    f.rms_source_to_patch = f.source_area > 0 ? std::sqrt(s2[p] / f.source_area) : 0.0;
  }
  out.rms_source_to_patches = w_source > 0 ? std::sqrt(s2_source / w_source) : 0.0;
  // Faces the mesher left without samples are unmeasured: uncovered.
  out.source_area = w_source + S.unmeshed_area;
  out.uncovered_area += S.unmeshed_area;
  out.coverage = out.source_area > 0 ? 1.0 - out.uncovered_area / out.source_area : 0.0;
  out.source_samples = static_cast<Index>(nS);
  out.triangle_uncovered = triangle_uncovered(surface, S, ds, tolerance);
  watch.lap("triangles");
}

}  // namespace

FitDeviation fit_deviation(const Surface& surface, const std::vector<BSplinePatch>& patches, double tolerance,
                           const DeviationOptions& options) {
  FitDeviation out;
  out.per_patch.assign(patches.size(), {});
  Stopwatch watch(out.timings);
  const Setup u = setup(surface, tolerance, options, out, watch);
  std::vector<double> ds;
  std::vector<Index> owner;
  source_to_patches(u, patches, options, ds, owner, out, watch);
  if (patches.empty()) return out;
  patches_to_source(surface, u, patches, tolerance, options, out, watch);
  source_figures(surface, u, ds, owner, tolerance, out, watch);
  return out;
}

FitDeviation patches_to_source_deviation(const Surface& surface, const std::vector<BSplinePatch>& patches,
                                         double tolerance, const DeviationOptions& options) {
  FitDeviation out;
  out.per_patch.assign(patches.size(), {});
  Stopwatch watch(out.timings);
  const Setup u = setup(surface, tolerance, options, out, watch);
  if (!patches.empty()) patches_to_source(surface, u, patches, tolerance, options, out, watch);
  return out;
}

void add_source_side(const Surface& surface, const std::vector<BSplinePatch>& patches, double tolerance,
                     const DeviationOptions& options, FitDeviation& partial) {
  Stopwatch watch(partial.timings);
  const Setup u = setup(surface, tolerance, options, partial, watch);
  std::vector<double> ds;
  std::vector<Index> owner;
  source_to_patches(u, patches, options, ds, owner, partial, watch);
  if (!patches.empty()) source_figures(surface, u, ds, owner, tolerance, partial, watch);
}

}  // namespace stripweave
