#include "stripweave/surface/build_surface.h"

#include "stripweave/cgal/jet_curvature.h"
#include "stripweave/cgal/mesh_io.h"
#include "stripweave/cgal/remesh.h"
#include "stripweave/cgal/simplify.h"
#include "stripweave/cgal/surface_locator.h"
#include "stripweave/core/error.h"
#include "stripweave/core/memory_guard.h"
#include "stripweave/core/parallel.h"
#include "stripweave/occt/brep_source.h"
#include "stripweave/surface/creases.h"
#include "stripweave/surface/feature_curves.h"
#include "stripweave/surface/sanitize_mesh.h"
#include "stripweave/surface/split_touching_edges.h"
#include "stripweave/surface/surface_report.h"
#include "stripweave/surface/zipper_fill.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace stripweave {

namespace {

void stage(Progress* p, const char* name, double begin, double end) {
  if (p) p->stage(name, begin, end);
}

double mesh_area(const TriangleMesh& m) {
  double a = 0;
  for (Index t = 0; t < m.num_triangles(); ++t) a += 0.5 * triangle_normal_area2(m, t).norm();
  return a;
}

// The target edge length for about `count` triangles over `area`. Equilateral
// triangles of edge L tile it with count = 4 area / (sqrt(3) L^2); CGAL's
// remeshing ends with edges somewhat shorter than its target (it splits above
// 4/3 L and collapses below 4/5 L), so the target is set about 10% longer.
double edge_length_for(double area, Index count) {
  return 1.1 * std::sqrt(4.0 * area / (std::sqrt(3.0) * count));
}

// A mesh input more than this many times the target is simplified before it
// is remeshed (simplify.h); below it the remesher alone is as fast, and the
// solver meshes of ordinary inputs stay as they were.
constexpr Index kSimplifyAbove = 8;

// Coordinates beyond this (model units) are no model's: every later product
// of a few of them must stay finite, the exact predicates' too.
constexpr double kMaxCoordinate = 1e100;

Similarity normalizing_similarity(const BoundingBox& box) {
  Similarity s;
  s.center = box.center();
  s.scale = box.diagonal();
  const double extent = std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
  if (!(extent <= kMaxCoordinate) || !std::isfinite(s.scale)) {
    std::ostringstream msg;
    msg << "the model's coordinates reach " << extent << " (at most " << kMaxCoordinate
        << "): its bounding-box diagonal is not a finite size";
    throw InputError(msg.str());
  }
  if (!(s.scale > 0)) throw InputError("the model has zero size (all its points coincide)");
  return s;
}

// Every number of the options, where it enters: a NaN feature angle dropped
// every crease, a negative target meant "keep the tessellation", a zero
// target on a 2M-triangle mesh ran for minutes.
void check_options(const SurfaceOptions& o) {
  auto fail = [](const std::string& what, double value) {
    std::ostringstream msg;
    msg << what << ", got " << value;
    throw InputError(msg.str());
  };
  if (!(o.feature_angle_deg > 0 && o.feature_angle_deg < 180))
    fail("the feature angle must be within (0, 180) degrees", o.feature_angle_deg);
  if (o.target_triangles < 0 || o.target_triangles > kMaxSolverTriangles)
    fail("the target triangle count must be 0 (keep the mesh) or up to " + std::to_string(kMaxSolverTriangles),
         o.target_triangles);
  if (!(o.deflection >= 0 && std::isfinite(o.deflection))) fail("the deflection must be 0 or a positive length", o.deflection);
  if (!(o.relative_deflection > 0 && o.relative_deflection <= 1))
    fail("the relative deflection must be within (0, 1]", o.relative_deflection);
  if (!(o.angular_deflection_deg > 0 && o.angular_deflection_deg < 180))
    fail("the angular deflection must be within (0, 180) degrees", o.angular_deflection_deg);
  if (!(o.min_feature_length >= 0 && o.min_feature_length <= 1))
    fail("the minimum feature length must be within [0, 1] (of the diagonal)", o.min_feature_length);
  if (!(o.curvature_radius >= 0 && o.curvature_radius <= 1))
    fail("the curvature radius must be within [0, 1] (of the diagonal; 0: automatic)", o.curvature_radius);
  if (o.remesh_iterations < 0 || o.remesh_iterations > 100)
    fail("the remeshing iterations must be within [0, 100]", o.remesh_iterations);
}

// The memory guard (core/memory_guard.h), before the stage allocates: with
// the input's triangle count once it is known (0 before), and the solver
// mesh's (the target, or the input kept as it is).
void check_surface_memory(Index input_triangles, const SurfaceOptions& o) {
  const Index solver = o.target_triangles > 0 ? o.target_triangles : input_triangles;
  std::ostringstream work;
  work << "building the surface (" << input_triangles << " input triangles, " << solver << " solver triangles)";
  check_memory(work.str(), surface_memory_mb(input_triangles, solver));
}

// A solver mesh kept as given (target 0) must fit the same bound as a target.
void check_kept_size(Index triangles, const SurfaceOptions& o) {
  if (o.target_triangles > 0 || triangles <= kMaxSolverTriangles) return;
  throw InputError("the model has " + std::to_string(triangles) + " triangles; a target of 0 keeps them all, over the "
                   "solver's limit of " + std::to_string(kMaxSolverTriangles) + ": give a target triangle count");
}

TriangleMesh transformed(const TriangleMesh& m, const Similarity& s) {
  TriangleMesh out = m;
  for (Vec3& p : out.positions) p = s.to_normalized(p);
  return out;
}

// Every vertex of `m` (normalized units) to its nearest point on `original`
// (model units).
void project_onto(const TriangleMesh& original, const Similarity& sim, TriangleMesh& m) {
  const SurfaceLocator locator(original);
  SurfacePoint3 hint;
  for (Index v = 0; v < m.num_vertices(); ++v) {
    const Vec3 p = sim.to_model(m.positions[v]);
    hint = hint.triangle == kInvalid ? locator.closest(p) : locator.closest(p, hint);
    m.positions[v] = sim.to_normalized(hint.point);
  }
}

std::vector<Vec3> area_weighted_normals(const TriangleMesh& m) {
  std::vector<Vec3> n(m.positions.size(), Vec3::Zero());
  for (Index t = 0; t < m.num_triangles(); ++t) {
    const Vec3 a = triangle_normal_area2(m, t);
    for (Index v : m.triangles[t]) n[v] += a;
  }
  for (Vec3& x : n) x = x.norm() > 0 ? Vec3(x.normalized()) : Vec3::UnitZ();
  return n;
}

// The common tail of both pipelines: connectivity, components, genus,
// boundary loops.
void finish_topology(Surface& s) {
  s.topology = MeshTopology::build(s.mesh);
  std::vector<Index> comp;
  s.components = triangle_components(s.topology, s.mesh.num_triangles(), comp);
  s.boundary_loops = boundary_loops(s.mesh, s.topology);
  s.genus = genus_from_euler(s.mesh.num_vertices(), s.topology.num_edges(), s.mesh.num_triangles(), s.components,
                             static_cast<Index>(s.boundary_loops.size()));
}

// Vertices where exact evaluation failed (poles, apexes) take the mean of
// their evaluated neighbours, spreading inward until all are set.
void fill_undefined_curvature(Surface& s, std::vector<std::uint8_t> defined) {
  const std::vector<Vec3> mesh_normal = area_weighted_normals(s.mesh);
  for (int round = 0; round < 64; ++round) {
    bool missing = false;
    std::vector<std::uint8_t> now = defined;
    for (Index v = 0; v < s.mesh.num_vertices(); ++v) {
      if (defined[v]) continue;
      double kmin = 0, kmax = 0;
      Vec3 dmax = Vec3::Zero();
      int n = 0;
      for (const Index* w = s.topology.vertex_neighbours.begin(v); w != s.topology.vertex_neighbours.end(v); ++w) {
        if (!defined[*w]) continue;
        kmin += s.k_min[*w], kmax += s.k_max[*w];
        dmax += s.d_max[*w].dot(dmax) < 0 ? Vec3(-s.d_max[*w]) : s.d_max[*w];
        ++n;
      }
      if (n == 0) {
        missing = true;
        continue;
      }
      const Vec3 nv = s.normal[v].squaredNorm() > 0 ? s.normal[v] : mesh_normal[v];
      s.normal[v] = nv;
      s.k_min[v] = kmin / n, s.k_max[v] = kmax / n;
      Vec3 t = dmax - dmax.dot(nv) * nv;
      if (t.norm() < 1e-12) t = (std::abs(nv.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(nv);
      s.d_max[v] = t.normalized();
      s.d_min[v] = nv.cross(s.d_max[v]);
      now[v] = 1;
    }
    defined.swap(now);
    if (!missing) return;
  }
  // A component with no evaluable point at all: flat fallback.
  for (Index v = 0; v < s.mesh.num_vertices(); ++v)
    if (!defined[v]) {
      s.normal[v] = mesh_normal[v];
      s.d_max[v] = (std::abs(mesh_normal[v].x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(mesh_normal[v]).normalized();
      s.d_min[v] = mesh_normal[v].cross(s.d_max[v]);
      s.k_min[v] = s.k_max[v] = 0;
    }
}

// BRepMesh sometimes leaves a hole where a face has a zero-length edge that
// is not flagged degenerate (fillet ends do this), or where one curve is
// discretized twice. A boundary loop of the welded mesh that does not run
// along a free B-rep edge is such a gap: close it (zipper_fill). Returns the
// number of gaps closed.
Index fill_tessellation_gaps(BrepTessellation& tess, const BrepSource& brep) {
  MeshTopology topo = MeshTopology::build(tess.mesh);
  std::set<EdgeKey> on_free_edge;
  for (size_t i = 0; i < tess.edge_segments.size(); ++i)
    if (brep.edge_face_count(tess.segment_edge[i]) < 2) on_free_edge.insert(tess.edge_segments[i]);
  Index filled = 0;
  for (const auto& loop : boundary_loops(tess.mesh, topo)) {
    bool free = false;
    for (size_t i = 0; i < loop.size() && !free; ++i)
      free = on_free_edge.count(edge_key(loop[i], loop[(i + 1) % loop.size()])) > 0;
    if (free || loop.size() < 3) continue;
    const Index face = tess.face_of_triangle[topo.edge_triangles[topo.find_edge(loop[0], loop[1])][0]];
    for (const Tri& t : zipper_fill(loop, tess.mesh.positions)) {
      tess.mesh.triangles.push_back(t);
      tess.face_of_triangle.push_back(face);
    }
    ++filled;
  }
  return filled;
}

}  // namespace

Surface surface_from_brep(std::shared_ptr<const BrepSource> brep, const SurfaceOptions& opt, Progress* progress) {
  check_options(opt);
  Surface s;
  Stopwatch clock(s.timings);
  stage(progress, "tessellating", 0.0, 0.3);
  check_surface_memory(0, opt);
  const BoundingBox box = brep->bounding_box();
  const double model_diag = box.diagonal();
  if (!(model_diag > 0)) throw InputError("the shape has zero size");
  const double deflection = opt.deflection > 0 ? opt.deflection : opt.relative_deflection * model_diag;
  s.warnings = brep->warnings();  // the sewing of loose faces
  BrepTessellation tess = brep->tessellate(deflection, opt.angular_deflection_deg * M_PI / 180.0);
  if (tess.mesh.triangles.empty()) throw InputError("OpenCASCADE produced no triangles for the shape");
  if (Index fins = part_touching_faces(tess.mesh, tess.face_of_triangle, tess.edge_segments, tess.corner_vertices))
    s.warnings.push_back("split " + std::to_string(fins) +
                         " mesh edge(s) where B-rep faces touch without a shared edge (split_touching_edges.h)");
  if (Index gaps = fill_tessellation_gaps(tess, *brep))
    s.warnings.push_back("closed " + std::to_string(gaps) + " gap(s) in OpenCASCADE's tessellation (a missing face or a curve discretized twice)");
  clock.lap("tessellate");
  s.input_triangles = tess.mesh.num_triangles();
  check_kept_size(s.input_triangles, opt);
  check_surface_memory(s.input_triangles, opt);
  s.brep = brep;
  s.brep_faces = brep->num_faces();
  s.similarity = normalizing_similarity(bounding_box(tess.mesh.positions));
  if (tess.unmeshed_faces > 0)
    s.warnings.push_back(std::to_string(tess.unmeshed_faces) + " B-rep face(s) could not be tessellated and are missing");

  stage(progress, "classifying edges", 0.3, 0.35);
  const std::vector<bool> sharp = brep->sharp_edges(opt.feature_angle_deg);
  clock.lap("sharp_edges");
  TriangleMesh mesh = transformed(tess.mesh, s.similarity);
  std::vector<Index> patch = tess.face_of_triangle;
  std::vector<Index> corners = tess.corner_vertices;
  // Per welded mesh edge: the B-rep edge it lies on (kInvalid inside faces).
  std::map<EdgeKey, Index> brep_edge_of;
  for (size_t i = 0; i < tess.edge_segments.size(); ++i) brep_edge_of[tess.edge_segments[i]] = tess.segment_edge[i];

  if (opt.target_triangles > 0) {
    stage(progress, "remeshing", 0.35, 0.75);
    // Every B-rep edge stays a polyline, so each new triangle keeps one source
    // face; seams are not borders and remeshing crosses them freely.
    std::vector<EdgeKey> constrained;
    for (const auto& [k, e] : brep_edge_of)
      if (brep->edge_face_count(e) < 2 || sharp[e]) constrained.push_back(k);
    const double target = edge_length_for(mesh_area(mesh), opt.target_triangles);
    RemeshResult r = remesh_isotropic(mesh, patch, constrained, corners, target, opt.remesh_iterations);
    mesh = std::move(r.mesh);
    patch = std::move(r.patch_of_triangle);
    corners = std::move(r.constrained_vertices);
    // Recover the B-rep edge of each border edge from the faces on its sides.
    brep_edge_of.clear();
    std::vector<std::vector<Index>> edges_of_face(brep->num_faces());
    for (Index f = 0; f < brep->num_faces(); ++f) edges_of_face[f] = brep->face_edges(f);
    MeshTopology topo = MeshTopology::build(mesh);
    for (Index e = 0; e < topo.num_edges(); ++e) {
      const auto& et = topo.edge_triangles[e];
      const Index fa = patch[et[0]], fb = et[1] == kInvalid ? kInvalid : patch[et[1]];
      if (fa == fb) continue;  // inside one face (or across a seam)
      // Candidates: edges of face fa that also bound fb (or are free edges).
      const Vec3 mid = s.similarity.to_model(0.5 * (mesh.positions[topo.edges[e][0]] + mesh.positions[topo.edges[e][1]]));
      Index best = kInvalid;
      double best_d = std::numeric_limits<double>::infinity();
      for (Index be : edges_of_face[fa]) {
        const bool shared = fb == kInvalid ? brep->edge_face_count(be) < 2
                                           : std::find(edges_of_face[fb].begin(), edges_of_face[fb].end(), be) !=
                                                 edges_of_face[fb].end();
        if (!shared) continue;
        double d;
        brep->project_to_edge(be, mid, &d);
        if (d < best_d) best_d = d, best = be;
      }
      if (best != kInvalid) brep_edge_of[topo.edges[e]] = best;
    }
    clock.lap("remesh");
  }

  stage(progress, "evaluating the B-rep", 0.75, 0.95);
  s.mesh = std::move(mesh);
  s.source_face = patch;
  finish_topology(s);
  const Index nv = s.mesh.num_vertices();
  s.normal.assign(nv, Vec3::Zero());
  s.d_min.assign(nv, Vec3::Zero());
  s.d_max.assign(nv, Vec3::Zero());
  s.k_min.assign(nv, 0.0);
  s.k_max.assign(nv, 0.0);
  std::vector<bool> is_corner(nv, false);
  std::vector<std::uint8_t> curvature_defined(nv, 0);  // bytes: written by several threads
  for (Index c : corners) is_corner[c] = true;
  // The B-rep edges each vertex lies on (from the edges around it).
  std::vector<Index> on_edge(nv, kInvalid);
  for (const auto& [k, be] : brep_edge_of)
    for (Index v : k) on_edge[v] = be;
  const double scale = s.similarity.scale;
  // Vertices are evaluated independently (evaluate and project_to_edge keep
  // no warm start), so on two cores, each with its own copy of the B-rep's
  // caches, with the same result: this loop was 1.9 of ec_soapbox-A's 2.6 s
  // of loading.
  const unsigned workers = parallel_workers(nv);
  std::vector<std::shared_ptr<BrepSource>> copies(workers);
  for (unsigned w = 1; w < workers; ++w) copies[w] = brep->thread_copy();
  parallel_for_workers(nv, [&](Index v, unsigned worker) {
    const BrepSource& b = worker == 0 ? *brep : *copies[worker];
    if (progress && worker == 0 && v % 1024 == 0) progress->advance(double(v) / nv);
    const Index face = patch[*s.topology.vertex_triangles.begin(v)];
    Vec3 p = s.similarity.to_model(s.mesh.positions[v]);
    // Remeshing left vertices on chords; put them back on the exact surface:
    // corners stay, edge vertices go onto their edge curve, the rest onto
    // their face.
    if (!is_corner[v] && on_edge[v] != kInvalid) p = b.project_to_edge(on_edge[v], p);
    const SurfacePoint sp = b.evaluate(face, p);
    if (!is_corner[v] && on_edge[v] == kInvalid) p = sp.position;
    s.mesh.positions[v] = s.similarity.to_normalized(p);
    if (!sp.normal_defined) return;
    s.normal[v] = sp.normal;
    if (!sp.curvature_defined) return;
    s.k_min[v] = sp.k_min * scale, s.k_max[v] = sp.k_max * scale;
    s.d_min[v] = sp.d_min, s.d_max[v] = sp.d_max;
    curvature_defined[v] = 1;
  });
  fill_undefined_curvature(s, std::move(curvature_defined));
  copies.clear();
  brep->release_caches();  // the loop's analysers: the later stages project elsewhere, or anew
  clock.lap("curvature");

  stage(progress, "chaining feature curves", 0.95, 1.0);
  std::vector<bool> is_feature(s.topology.num_edges(), false);
  for (Index e = 0; e < s.topology.num_edges(); ++e) {
    auto it = brep_edge_of.find(s.topology.edges[e]);
    is_feature[e] = it != brep_edge_of.end() && sharp[it->second];
  }
  s.edge_class = classify_edges(s.topology, is_feature);
  // Feature curves follow the CAD edges: a chain breaks at every B-rep vertex.
  s.feature_curves = chain_feature_curves(s.mesh, s.topology, s.edge_class, is_corner, 0.0, s.edge_curve);
  clock.lap("features");
  return s;
}

Surface surface_from_mesh(const TriangleMesh& raw, const SurfaceOptions& opt, Progress* progress) {
  check_options(opt);
  Surface s;
  Stopwatch clock(s.timings);
  stage(progress, "checking the mesh", 0.0, 0.15);
  check_surface_memory(raw.num_triangles(), opt);
  SanitizedMesh clean = sanitize_mesh(raw);
  s.input_triangles = clean.mesh.num_triangles();
  check_kept_size(s.input_triangles, opt);
  clock.lap("sanitize");
  s.warnings = clean.warnings;
  s.source_mesh = std::make_shared<const TriangleMesh>(clean.mesh);
  s.similarity = normalizing_similarity(bounding_box(clean.mesh.positions));
  TriangleMesh mesh = transformed(clean.mesh, s.similarity);

  stage(progress, "finding sharp features", 0.15, 0.25);
  MeshTopology topo = MeshTopology::build(mesh);
  std::vector<EdgeClass> classes = classify_edges(topo, dihedral_feature_edges(mesh, topo, opt.feature_angle_deg));
  std::vector<Index> edge_curve;
  std::vector<FeatureCurve> curves =
      chain_feature_curves(mesh, topo, classes, {}, opt.min_feature_length, edge_curve);
  // The one crease set (creases.h), decided before remeshing so that the
  // remesher protects only creases and smooths the noise ridges away.
  keep_crease_curves(mesh, topo, classes, curves, edge_curve);
  clock.lap("features");

  if (opt.target_triangles > 0) {
    stage(progress, "remeshing", 0.25, 0.7);
    std::vector<EdgeKey> constrained;
    for (Index e = 0; e < topo.num_edges(); ++e)
      if (classes[e] != EdgeClass::Regular) constrained.push_back(topo.edges[e]);
    // Curve ends and corners must survive, or chains would merge or vanish.
    std::set<Index> ends;
    for (const auto& c : curves)
      if (!c.closed) ends.insert(c.vertices.front()), ends.insert(c.vertices.back());
    const double target = edge_length_for(mesh_area(mesh), opt.target_triangles);
    std::vector<Index> fixed(ends.begin(), ends.end());
    if (mesh.num_triangles() > kSimplifyAbove * opt.target_triangles) {
      // A scan far denser than the solver mesh: collapse its short edges first
      // (shortest first, to half the target length: about four times the target
      // count), so the remesher's own collapsing starts near its size (§8.1).
      SimplifyResult coarse = simplify_short_edges(mesh, constrained, fixed, 0.5 * target);
      mesh = std::move(coarse.mesh);
      constrained = std::move(coarse.constrained_edges);
      fixed = std::move(coarse.constrained_vertices);
      clock.lap("simplify");
    }
    const bool simplified = mesh.num_triangles() < s.source_mesh->num_triangles();
    RemeshResult r = remesh_isotropic(mesh, std::vector<Index>(mesh.num_triangles(), 0), constrained, fixed, target,
                                      opt.remesh_iterations);
    mesh = std::move(r.mesh);
    topo = MeshTopology::build(mesh);
    std::vector<bool> is_feature(topo.num_edges(), false);
    std::set<EdgeKey> kept(r.constrained_edges.begin(), r.constrained_edges.end());
    for (Index e = 0; e < topo.num_edges(); ++e) is_feature[e] = kept.count(topo.edges[e]) > 0;
    classes = classify_edges(topo, is_feature);
    std::vector<bool> is_end(mesh.num_vertices(), false);
    for (Index v : r.constrained_vertices) is_end[v] = true;
    curves = chain_feature_curves(mesh, topo, classes, is_end, 0.0, edge_curve);
    clock.lap("remesh");
    if (simplified) {
      // The remesher projected onto the simplified mesh, whose collapsed
      // vertices sit on chords: put the proxy's vertices on the original
      // (the correspondence by projection; feature and boundary vertices are
      // the original's own, or on its polylines, and stay).
      project_onto(*s.source_mesh, s.similarity, mesh);
      clock.lap("project");
    }
  }
  s.mesh = std::move(mesh);
  finish_topology(s);
  s.edge_class = std::move(classes);
  s.edge_curve = std::move(edge_curve);
  s.feature_curves = std::move(curves);
  s.source_face.assign(s.mesh.num_triangles(), kInvalid);

  stage(progress, "estimating curvature", 0.7, 1.0);
  double mean_edge = 0;
  for (const EdgeKey& e : s.topology.edges) mean_edge += (s.mesh.positions[e[0]] - s.mesh.positions[e[1]]).norm();
  mean_edge /= std::max<Index>(1, s.topology.num_edges());
  const double radius = opt.curvature_radius > 0 ? opt.curvature_radius : std::max(0.015, 2.0 * mean_edge);
  CurvatureField field = jet_fit_curvature(s.mesh, radius);
  s.normal = std::move(field.normal);
  s.k_min = std::move(field.k_min);
  s.k_max = std::move(field.k_max);
  s.d_min = std::move(field.d_min);
  s.d_max = std::move(field.d_max);
  clock.lap("curvature");
  return s;
}

Surface load_surface(const std::string& path, const SurfaceOptions& options, Progress* progress) {
  check_options(options);  // before reading: a bad option is refused at once, not after a big file
  // Reading is timed here, so `bench` sees it as the first stage.
  StageTimings read_time;
  Stopwatch clock(read_time);
  Surface s;
  if (is_brep_file(path)) {
    if (progress) progress->stage("reading", 0.0, 0.0);
    auto brep = BrepSource::from_file(path);
    clock.lap("read");
    s = surface_from_brep(brep, options, progress);
  } else if (is_mesh_file(path)) {
    TriangleMesh raw = read_mesh_file(path);
    clock.lap("read");
    s = surface_from_mesh(raw, options, progress);
  } else {
    throw InputError("unknown model format '" + path + "' (expected STEP, IGES, BREP, STL, OBJ, OFF or PLY)");
  }
  s.timings.insert(s.timings.begin(), read_time.begin(), read_time.end());
  return s;
}

}  // namespace stripweave
