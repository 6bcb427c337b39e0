#include "stripweave/occt/brep_source.h"
#include "stripweave/occt/occt_messages.h"
#include "stripweave/occt/brep_source_impl.h"
#include "stripweave/occt/sew_loose_faces.h"

#include "stripweave/core/error.h"
#include "stripweave/core/union_find.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Adaptor3d_Surface.hxx>
#include <Bnd_Box.hxx>
#include <Extrema_ExtPC.hxx>
#include <Geom2d_Curve.hxx>
#include <GeomAdaptor_Surface.hxx>
#include <Geom_Surface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

namespace stripweave {

namespace {

Vec3 to_vec(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }
Vec3 to_vec(const gp_Dir& d) { return {d.X(), d.Y(), d.Z()}; }
gp_Pnt to_pnt(const Vec3& p) { return gp_Pnt(p.x(), p.y(), p.z()); }

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}


// The shape as FreeCAD hands it over: written as BREP text and read back.
// A STEP or IGES reader's shape and the same shape after that round trip
// hold the same geometry, but the mesher meets their faces and edges in
// another order, and an edge is discretized once, for the face met first:
// a filleted box read from STEP meshed into 1,516 triangles, and into 1,564
// through FreeCAD (Part.read, Import.insert and the file's BREP alike), so
// the solver meshes differed (28,238 against 28,742 triangles) and a design
// the command line wove could refuse its strips in the workbench.
TopoDS_Shape as_handed_over(const TopoDS_Shape& shape) {
  std::stringstream text;
  BRepTools::Write(shape, text);
  TopoDS_Shape back;
  BRep_Builder builder;
  BRepTools::Read(back, text, builder);
  return back.IsNull() ? shape : back;
}

}  // namespace

BrepSource::BrepSource(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
BrepSource::~BrepSource() = default;

std::shared_ptr<BrepSource> BrepSource::from_file(const std::string& path) {
  quiet_occt_messages();
  namespace fs = std::filesystem;
  if (!fs::exists(path)) throw InputError("cannot read '" + path + "': the file does not exist");
  if (fs::is_directory(path)) throw InputError("cannot read '" + path + "': it is a directory");
  if (!fs::is_regular_file(path))  // a FIFO or a device is read forever
    throw InputError("cannot read '" + path + "': it is not a regular file (a device, pipe or socket)");
  if (fs::file_size(path) == 0) throw InputError("cannot read '" + path + "': the file is empty");
  const std::string ext = lower_extension(path);
  TopoDS_Shape shape;
  try {
    if (ext == ".step" || ext == ".stp") {
      STEPControl_Reader reader;
      if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
        throw InputError("cannot read '" + path + "': not a valid STEP file");
      if (reader.TransferRoots() == 0) throw InputError("'" + path + "' holds no shape that can be transferred");
      shape = reader.OneShape();
    } else if (ext == ".iges" || ext == ".igs") {
      IGESControl_Reader reader;
      if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
        throw InputError("cannot read '" + path + "': not a valid IGES file");
      if (reader.TransferRoots() == 0) throw InputError("'" + path + "' holds no shape that can be transferred");
      shape = reader.OneShape();
    } else if (ext == ".brep" || ext == ".brp") {
      BRep_Builder builder;
      if (!BRepTools::Read(shape, path.c_str(), builder) || shape.IsNull())
        throw InputError("cannot read '" + path + "': not a valid BREP file");
    } else {
      throw InputError("unknown CAD format '" + ext + "' (expected .step, .stp, .iges, .igs, .brep or .brp)");
    }
    if (ext != ".brep" && ext != ".brp") shape = as_handed_over(shape);
  } catch (const Standard_Failure& f) {
    throw InputError("cannot read '" + path + "': " + f.GetMessageString());
  }
  return checked(std::make_unique<Impl>(shape), "'" + path + "'");
}

std::shared_ptr<BrepSource> BrepSource::from_brep_string(const std::string& text) {
  quiet_occt_messages();
  if (text.empty()) throw InputError("the BREP text is empty");
  TopoDS_Shape shape;
  try {
    std::istringstream in(text);
    BRep_Builder builder;
    BRepTools::Read(shape, in, builder);
  } catch (const Standard_Failure& f) {
    throw InputError(std::string("not a valid BREP text: ") + f.GetMessageString());
  }
  if (shape.IsNull()) throw InputError("not a valid BREP text: no shape could be read");
  return checked(std::make_unique<Impl>(shape), "the shape");
}

std::shared_ptr<BrepSource> BrepSource::checked(std::unique_ptr<Impl> impl, const std::string& what) {
  if (impl->faces.Extent() == 0) throw InputError(what + " has no faces (only wires, edges or vertices)");
  std::vector<std::string> warnings;
  const TopoDS_Shape sewn = sew_loose_faces(impl->shape, warnings);
  if (!warnings.empty()) {
    impl = std::make_unique<Impl>(sewn);
    impl->warnings = std::move(warnings);
  }
  Index overloaded = 0;
  for (Index e = 0; e < impl->edges.Extent(); ++e)
    if (impl->faces_of_edge(e).size() > 2 || impl->edge_use_count(e) > 2) ++overloaded;
  if (overloaded > 0)
    throw InputError(what + " is non-manifold: " + std::to_string(overloaded) +
                     (overloaded == 1 ? " edge is" : " edges are") + " shared by more than two faces");
  return std::shared_ptr<BrepSource>(new BrepSource(std::move(impl)));
}

std::shared_ptr<BrepSource> BrepSource::thread_copy() const {
  auto impl = std::make_unique<Impl>(impl_->shape);
  impl->start_grids = impl_->start_grids;  // the face's alone: shared, built once
  return std::shared_ptr<BrepSource>(new BrepSource(std::move(impl)));
}

ShapeAnalysis_Surface& BrepSource::Impl::analyser(Index f) const {
  if (!analysers[f]) analysers[f] = std::make_unique<ShapeAnalysis_Surface>(BRep_Tool::Surface(face(f)));
  return *analysers[f];
}

gp_Pnt2d BrepSource::Impl::global_uv(Index f, const gp_Pnt& p) const {
  ShapeAnalysis_Surface& a = analyser(f);
  switch (a.Adaptor3d()->GetType()) {
    case GeomAbs_Plane: case GeomAbs_Cylinder: case GeomAbs_Cone: case GeomAbs_Sphere: case GeomAbs_Torus:
      return a.ValueOfUV(p, 1e-9);  // in closed form: no grid
    default:
      break;
  }
  if (searched_at[f] == 0 && held_grids >= kSearchGrids) {
    Index oldest = kInvalid;
    for (Index g = 0; g < static_cast<Index>(searched_at.size()); ++g)
      if (searched_at[g] != 0 && (oldest == kInvalid || searched_at[g] < searched_at[oldest])) oldest = g;
    analysers[oldest].reset();
    searched_at[oldest] = 0;
    --held_grids;
  }
  if (searched_at[f] == 0) ++held_grids;
  searched_at[f] = ++search_clock;
  return a.ValueOfUV(p, 1e-9);
}

Index BrepSource::held_search_grids() const { return impl_->held_grids; }

void BrepSource::release_caches() const {
  Impl& s = *impl_;
  for (auto& a : s.analysers) a.reset();
  std::fill(s.searched_at.begin(), s.searched_at.end(), 0);
  s.held_grids = 0;
  for (auto& c : s.classifiers) c.reset();
  for (auto& a : s.adaptors) a.reset();
  for (auto& c : s.edge_curves) c.reset();
}

void BrepSource::forget_warm_starts() const { std::fill(impl_->has_last_uv.begin(), impl_->has_last_uv.end(), 0); }

const std::vector<std::string>& BrepSource::warnings() const { return impl_->warnings; }

Index BrepSource::num_faces() const { return impl_->faces.Extent(); }
Index BrepSource::num_edges() const { return impl_->edges.Extent(); }

namespace {

// From the geometry, not a tessellation (conservative: never smaller).
BoundingBox box_of(const TopoDS_Shape& shape) {
  Bnd_Box box;
  BRepBndLib::Add(shape, box, /*useTriangulation=*/false);
  BoundingBox result;
  if (box.IsVoid()) return result;
  double x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  result.add({x0, y0, z0});
  result.add({x1, y1, z1});
  return result;
}

}  // namespace

BoundingBox BrepSource::bounding_box() const { return box_of(impl_->shape); }

BoundingBox BrepSource::face_bounding_box(Index face) const { return box_of(impl_->face(face)); }

BoundingBox BrepSource::edge_bounding_box(Index edge) const { return box_of(impl_->edge(edge)); }

BrepTessellation BrepSource::tessellate(double linear_deflection, double angular_deflection_rad) const {
  const Impl& s = *impl_;
  // Reuse of an existing triangulation would make results depend on who
  // meshed the shape before (FreeCAD's view does); start clean.
  BRepTools::Clean(s.shape);
  try {
    BRepMesh_IncrementalMesh mesher(s.shape, linear_deflection, false, angular_deflection_rad, false);
  } catch (const Standard_Failure& f) {
    throw InputError(std::string("OpenCASCADE could not tessellate the shape: ") + f.GetMessageString());
  }

  BrepTessellation out;
  const Index nf = num_faces();
  std::vector<Handle(Poly_Triangulation)> tri(nf);
  std::vector<TopLoc_Location> loc(nf);
  std::vector<Index> slot_offset(nf + 1, 0);
  for (Index f = 0; f < nf; ++f) {
    tri[f] = BRep_Tool::Triangulation(s.face(f), loc[f]);
    if (tri[f].IsNull() || tri[f]->NbTriangles() == 0) {
      ++out.unmeshed_faces;
      tri[f].Nullify();
    }
    slot_offset[f + 1] = slot_offset[f] + (tri[f].IsNull() ? 0 : tri[f]->NbNodes());
  }

  // Every node of every face triangulation is a slot; slots that stand for
  // the same point of a shared edge or vertex are united. BRepMesh discretizes
  // each edge once, so the k-th node of an edge's polygon is the same point
  // in every face that uses the edge.
  UnionFind sets(slot_offset[nf]);
  std::map<std::pair<Index, Index>, Index> key_slot;  // (edge, k) or (-1-vertex, 0)
  auto bind = [&](std::pair<Index, Index> key, Index slot) {
    auto [it, inserted] = key_slot.emplace(key, slot);
    if (!inserted) sets.unite(it->second, slot);
  };
  std::vector<std::array<Index, 3>> segments;  // slot, slot, edge
  std::set<Index> corner_slots;
  for (Index f = 0; f < nf; ++f) {
    if (tri[f].IsNull()) continue;
    for (TopExp_Explorer ex(s.face(f), TopAbs_EDGE); ex.More(); ex.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(ex.Current());
      const Index e = s.edges.FindIndex(edge) - 1;
      const Handle(Poly_PolygonOnTriangulation)& poly = BRep_Tool::PolygonOnTriangulation(edge, tri[f], loc[f]);
      if (poly.IsNull()) continue;
      const TColStd_Array1OfInteger& nodes = poly->Nodes();
      const Index n = nodes.Length();
      TopoDS_Vertex v_first, v_last;
      TopExp::Vertices(TopoDS::Edge(edge.Oriented(TopAbs_FORWARD)), v_first, v_last);
      // Count nodes from the edge's first parameter, whatever the polygon's order.
      const bool reversed = poly->HasParameters() && n > 1 && poly->Parameter(nodes.Lower()) > poly->Parameter(nodes.Upper());
      for (Index i = 0; i < n; ++i) {
        const Index k = reversed ? n - 1 - i : i;
        const Index slot = slot_offset[f] + nodes(nodes.Lower() + i) - 1;
        if (BRep_Tool::Degenerated(edge) || k == 0 || k == n - 1) {
          const TopoDS_Vertex& v = (k == 0 || BRep_Tool::Degenerated(edge)) ? v_first : v_last;
          if (!v.IsNull()) {
            bind({-1 - (s.vertices.FindIndex(v) - 1), 0}, slot);
            corner_slots.insert(slot);
            continue;
          }
        }
        bind({e, k}, slot);
      }
      if (!BRep_Tool::Degenerated(edge))
        for (Index i = 0; i + 1 < n; ++i)
          segments.push_back({slot_offset[f] + nodes(nodes.Lower() + i) - 1,
                              slot_offset[f] + nodes(nodes.Lower() + i + 1) - 1, e});
    }
  }

  std::vector<Index> vertex_of_root(slot_offset[nf], kInvalid);
  auto vertex_of = [&](Index slot) {
    const Index root = sets.find(slot);
    if (vertex_of_root[root] == kInvalid) {
      vertex_of_root[root] = out.mesh.num_vertices();
      Index f = static_cast<Index>(std::upper_bound(slot_offset.begin(), slot_offset.end(), root) - slot_offset.begin()) - 1;
      const gp_Pnt p = tri[f]->Node(root - slot_offset[f] + 1).Transformed(loc[f].Transformation());
      out.mesh.positions.push_back(to_vec(p));
    }
    return vertex_of_root[root];
  };
  for (Index f = 0; f < nf; ++f) {
    if (tri[f].IsNull()) continue;
    const bool flip = s.face(f).Orientation() == TopAbs_REVERSED;
    for (Index t = 1; t <= tri[f]->NbTriangles(); ++t) {
      Standard_Integer a, b, c;
      tri[f]->Triangle(t).Get(a, b, c);
      if (flip) std::swap(b, c);
      const Tri tv = {vertex_of(slot_offset[f] + a - 1), vertex_of(slot_offset[f] + b - 1),
                      vertex_of(slot_offset[f] + c - 1)};
      if (tv[0] == tv[1] || tv[1] == tv[2] || tv[2] == tv[0]) {
        ++out.collapsed_triangles;  // a fan at a pole or on a degenerate edge
        continue;
      }
      out.mesh.triangles.push_back(tv);
      out.face_of_triangle.push_back(f);
    }
  }
  std::set<std::pair<EdgeKey, Index>> seen;
  for (const auto& [a, b, e] : segments) {
    const EdgeKey k = edge_key(vertex_of(a), vertex_of(b));
    if (k[0] == k[1] || !seen.insert({k, e}).second) continue;
    out.edge_segments.push_back(k);
    out.segment_edge.push_back(e);
  }
  std::set<Index> corners;
  for (Index slot : corner_slots) corners.insert(vertex_of(slot));
  out.corner_vertices.assign(corners.begin(), corners.end());
  return out;
}

Index BrepSource::edge_face_count(Index e) const {
  return static_cast<Index>(std::min<Index>(2, impl_->edge_use_count(e)));
}

std::vector<Index> BrepSource::face_edges(Index face) const {
  std::vector<Index> result;
  for (TopExp_Explorer ex(impl_->face(face), TopAbs_EDGE); ex.More(); ex.Next()) {
    const Index e = impl_->edges.FindIndex(ex.Current()) - 1;
    if (std::find(result.begin(), result.end(), e) == result.end()) result.push_back(e);
  }
  return result;
}

std::vector<bool> BrepSource::sharp_edges(double angle_deg) const {
  const Impl& s = *impl_;
  const double cos_limit = std::cos(angle_deg * M_PI / 180.0);
  std::vector<bool> sharp(num_edges(), false);
  constexpr int kSamples = 9;  // along the edge: a dihedral may vary (a blend running out)
  for (Index e = 0; e < num_edges(); ++e) {
    const TopoDS_Edge& edge = s.edge(e);
    if (BRep_Tool::Degenerated(edge)) continue;
    const std::vector<Index> fs = s.faces_of_edge(e);
    if (fs.size() != 2) continue;  // free edge (boundary) or seam
    double first, last;
    Handle(Geom2d_Curve) pc[2];
    BRepAdaptor_Surface surf[2] = {BRepAdaptor_Surface(s.face(fs[0])), BRepAdaptor_Surface(s.face(fs[1]))};
    bool ok = true;
    for (int i = 0; i < 2; ++i) {
      pc[i] = BRep_Tool::CurveOnSurface(edge, s.face(fs[i]), first, last);
      ok = ok && !pc[i].IsNull();
    }
    if (!ok) continue;
    for (int j = 0; j < kSamples && !sharp[e]; ++j) {
      const double t = first + (last - first) * (j + 0.5) / kSamples;
      Vec3 n[2];
      bool defined = true;
      for (int i = 0; i < 2; ++i) {
        const gp_Pnt2d uv = pc[i]->Value(t);
        BRepLProp_SLProps props(surf[i], uv.X(), uv.Y(), 1, 1e-9);
        if (!props.IsNormalDefined()) {
          defined = false;
          break;
        }
        n[i] = to_vec(props.Normal());
        if (s.face(fs[i]).Orientation() == TopAbs_REVERSED) n[i] = -n[i];
      }
      if (defined && n[0].dot(n[1]) < cos_limit) sharp[e] = true;
    }
  }
  return sharp;
}

SurfacePoint BrepSource::evaluate(Index face, const Vec3& p) const {
  const Impl& s = *impl_;
  const TopoDS_Face& f = s.face(face);
  SurfacePoint result;
  try {
    const gp_Pnt2d uv = s.global_uv(face, to_pnt(p));
    BRepAdaptor_Surface surface(f, /*restriction=*/false);
    BRepLProp_SLProps props(surface, uv.X(), uv.Y(), 2, 1e-9);
    result.position = to_vec(props.Value());
    result.distance = (result.position - p).norm();
    // OCCT's normal is dU x dV; a reversed face's outward normal is its opposite.
    const double side = f.Orientation() == TopAbs_REVERSED ? -1.0 : 1.0;
    if (!props.IsNormalDefined()) return result;
    result.normal_defined = true;
    result.normal = side * to_vec(props.Normal());
    if (!props.IsCurvatureDefined()) return result;
    // OCCT measures curvature against dU x dV: positive when the surface
    // bends toward that normal. Ours is positive where convex, i.e. bending
    // away from the outward normal: k_ours = -side * k_occt, and negation
    // swaps which of the two is the minimum.
    const double kmax = props.MaxCurvature(), kmin = props.MinCurvature();
    Vec3 dmax, dmin;
    if (props.IsUmbilic()) {
      const Vec3 n = result.normal;
      dmax = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
      dmin = n.cross(dmax);
    } else {
      gp_Dir gmax, gmin;
      props.CurvatureDirections(gmax, gmin);
      dmax = to_vec(gmax), dmin = to_vec(gmin);
    }
    if (side > 0) {
      result.k_min = -kmax, result.d_min = dmax;
      result.k_max = -kmin, result.d_max = dmin;
    } else {
      result.k_min = kmin, result.d_min = dmin;
      result.k_max = kmax, result.d_max = dmax;
    }
    result.curvature_defined = true;
  } catch (const Standard_Failure&) {
    // Singular parameterizations (poles, apexes) leave the values undefined;
    // the caller fills them from neighbours.
  }
  return result;
}

Vec3 BrepSource::project_to_edge(Index e, const Vec3& p, double* distance) const {
  const TopoDS_Edge& edge = impl_->edge(e);
  Vec3 best = p;
  double best_d = std::numeric_limits<double>::infinity();
  if (!BRep_Tool::Degenerated(edge)) {
    try {
      std::unique_ptr<Impl::EdgeCurve>& cached = impl_->edge_curves[e];
      if (!cached) cached = std::make_unique<Impl::EdgeCurve>(edge);
      const BRepAdaptor_Curve& curve = cached->curve;
      Extrema_ExtPC& ext = cached->extrema;
      ext.Perform(to_pnt(p));
      if (ext.IsDone())
        for (int i = 1; i <= ext.NbExt(); ++i)
          if (ext.SquareDistance(i) < best_d) best_d = ext.SquareDistance(i), best = to_vec(ext.Point(i).Value());
      // The ends are not always extrema.
      for (double t : {curve.FirstParameter(), curve.LastParameter()}) {
        const Vec3 q = to_vec(curve.Value(t));
        if ((q - p).squaredNorm() < best_d) best_d = (q - p).squaredNorm(), best = q;
      }
    } catch (const Standard_Failure&) {
    }
  }
  if (distance) *distance = std::sqrt(best_d);
  return best;
}

namespace {

// The foot point of p on a surface by a local search from `start`: Newton
// on the squared distance (Gauss-Newton, each step halved until it brings
// the point nearer), kept within the surface's parameter bounds but along a
// periodic direction, until the full step, or the last one taken, moves
// the point by at most 1e-10 of the face's size. False when it does not
// settle within 30 steps, or no point along a step is nearer while the
// step is not yet that small.
// Why not OCCT's NextValueOfUV: it gives up, and searches the whole surface
// (a grid of distances: milliseconds on a B-spline face), as soon as a step
// leaves the bounds, which every sample by a face border does when it is
// projected onto the neighbouring face; this search settles on the border
// there, the point the global search finds too.
bool local_foot(ShapeAnalysis_Surface& analyser, const gp_Pnt& p, const gp_Pnt2d& start, double scale,
                gp_Pnt2d& foot, bool& on_border) {
  const Handle(GeomAdaptor_Surface)& surface = analyser.Adaptor3d();
  double u0, u1, v0, v1;
  analyser.Bounds(u0, u1, v0, v1);
  const bool periodic_u = surface->IsUPeriodic(), periodic_v = surface->IsVPeriodic();
  // Along a periodic direction the parameter is wrapped into its first
  // period, not clamped: a free one drifts by whole periods over the samples
  // of a closed face (a fillet's torus), and the trim classifier
  // (BRepTopAdaptor_FClass2d) took minutes per point far outside the face's
  // parameter range (a rounded box's refit never ended).
  auto wrap = [](double x, double lo, double period) {
    return period > 0 ? lo + std::fmod(std::fmod(x - lo, period) + period, period) : x;
  };
  const double period_u = periodic_u ? surface->UPeriod() : 0, period_v = periodic_v ? surface->VPeriod() : 0;
  auto clamp = [&](double u, double v) {
    return gp_Pnt2d(periodic_u ? wrap(u, u0, period_u) : std::clamp(u, u0, u1),
                    periodic_v ? wrap(v, v0, period_v) : std::clamp(v, v0, v1));
  };
  gp_Pnt2d uv = clamp(start.X(), start.Y());
  gp_Pnt S;
  gp_Vec Su, Sv;
  surface->D1(uv.X(), uv.Y(), S, Su, Sv);
  double best = S.SquareDistance(p);
  const double settled = 1e-10 * scale;
  for (int it = 0; it < 30; ++it) {
    const gp_Vec r(S, p);
    const double a = Su.Dot(Su), b = Su.Dot(Sv), c = Sv.Dot(Sv);
    const double det = a * c - b * b;
    if (!(std::abs(det) > 1e-300)) return false;
    const double gu = Su.Dot(r), gv = Sv.Dot(r);
    double du = (c * gu - b * gv) / det, dv = (a * gv - b * gu) / det;
    // On a border with the step pointing out: that coordinate stays, the
    // other one follows the distance along the border (a clamped joint step
    // could stall short of the border's foot point).
    const bool out_u = !periodic_u && ((uv.X() <= u0 && du < 0) || (uv.X() >= u1 && du > 0));
    const bool out_v = !periodic_v && ((uv.Y() <= v0 && dv < 0) || (uv.Y() >= v1 && dv > 0));
    if (out_u && out_v) {
      foot = uv;
      on_border = (!periodic_u && (uv.X() <= u0 || uv.X() >= u1)) || (!periodic_v && (uv.Y() <= v0 || uv.Y() >= v1));
      return true;
    }
    if (out_u) du = 0, dv = c > 0 ? gv / c : 0;
    if (out_v) dv = 0, du = a > 0 ? gu / a : 0;
    if ((du * Su + dv * Sv).Magnitude() <= settled) {
      foot = uv;
      on_border = (!periodic_u && (uv.X() <= u0 || uv.X() >= u1)) || (!periodic_v && (uv.Y() <= v0 || uv.Y() >= v1));
      return true;
    }
    bool better = false;
    double moved = 0;
    for (int half = 0; half < 10 && !better; ++half, du *= 0.5, dv *= 0.5) {
      const gp_Pnt2d next = clamp(uv.X() + du, uv.Y() + dv);
      gp_Pnt T;
      gp_Vec Tu, Tv;
      surface->D1(next.X(), next.Y(), T, Tu, Tv);
      const double d = T.SquareDistance(p);
      if (d < best) moved = T.Distance(S), best = d, uv = next, S = T, Su = Tu, Sv = Tv, better = true;
    }
    // No nearer point along a step that is not yet negligible: no answer
    // (the global search decides).
    if (!better) return false;
    if (moved <= settled) {
      foot = uv;
      on_border = (!periodic_u && (uv.X() <= u0 || uv.X() >= u1)) || (!periodic_v && (uv.Y() <= v0 || uv.Y() >= v1));
      return true;
    }
  }
  return false;
}

// Start points for a local foot-point search on one face: its surface sampled on a grid over
// the face's (u, v) box (BRepTools::UVBounds: the trim's, not the surface's, which is infinite
// for a plane), fine enough that neighbouring samples' normals turn by at most kStartTurn (a
// thread's helical face gets samples along every turn) and lie at most kStartStep of the
// face's size apart, at most kMaxStartSamples in all. The grid depends on the face alone, so
// every thread copy starts from the same points.
constexpr double kStartTurn = 0.26;      // radians, 15 degrees
constexpr double kStartStep = 1.0 / 64;  // of the face's size
constexpr int kMinStartSide = 16, kMaxStartSide = 512, kMaxStartSamples = 1 << 16;

// The start grid's sample counts along u and v, from the largest turn of the normals and the
// largest step between neighbours of a kMinStartSide grid (both fall linearly with the
// spacing). The step bound: where two parts of the face lie almost equally near p (the two
// walls of a thread's groove), the start falls in the farther one's basin only when the
// nearer foot lies about a step from every sample.
std::pair<int, int> start_grid_sides(const Adaptor3d_Surface& surface, double u0, double u1, double v0, double v1) {
  const int n = kMinStartSide;
  std::vector<gp_Vec> N((n + 1) * (n + 1));
  std::vector<gp_Pnt> X((n + 1) * (n + 1));
  Bnd_Box box;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const int k = i * (n + 1) + j;
      gp_Vec Su, Sv;
      surface.D1(u0 + (u1 - u0) * i / n, v0 + (v1 - v0) * j / n, X[k], Su, Sv);
      N[k] = Su.Crossed(Sv);
      box.Add(X[k]);
    }
  auto angle = [](const gp_Vec& a, const gp_Vec& b) {
    return a.Magnitude() > 1e-300 && b.Magnitude() > 1e-300 ? a.Angle(b) : 0.0;
  };
  double turn_u = 0, turn_v = 0, step_u = 0, step_v = 0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const int k = i * (n + 1) + j;
      if (i < n) turn_u = std::max(turn_u, angle(N[k], N[k + n + 1])), step_u = std::max(step_u, X[k].Distance(X[k + n + 1]));
      if (j < n) turn_v = std::max(turn_v, angle(N[k], N[k + 1])), step_v = std::max(step_v, X[k].Distance(X[k + 1]));
    }
  const double size = box.IsVoid() ? 0.0 : std::sqrt(box.SquareExtent());
  auto side = [&](double turn, double step) {
    const double by_turn = n * turn / kStartTurn, by_step = size > 0 ? n * step / (kStartStep * size) : 0.0;
    return std::clamp(int(std::ceil(std::max(by_turn, by_step))), n, kMaxStartSide);
  };
  int nu = side(turn_u, step_u), nv = side(turn_v, step_v);
  while ((nu + 1) * (nv + 1) > kMaxStartSamples) nu = std::max(n, nu * 3 / 4), nv = std::max(n, nv * 3 / 4);
  return {nu, nv};
}

std::unique_ptr<BrepSource::Impl::StartGrid> start_grid(const TopoDS_Face& face, const Adaptor3d_Surface& surface) {
  auto grid = std::make_unique<BrepSource::Impl::StartGrid>();
  double u0, u1, v0, v1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  if (!(u1 > u0) || !(v1 > v0) || !std::isfinite(u1 - u0) || !std::isfinite(v1 - v0)) return grid;
  const auto [nu, nv] = start_grid_sides(surface, u0, u1, v0, v1);
  std::vector<Vec3> xyz;
  xyz.reserve((nu + 1) * (nv + 1));
  grid->uv.reserve((nu + 1) * (nv + 1));
  gp_Pnt S;
  for (int i = 0; i <= nu; ++i)
    for (int j = 0; j <= nv; ++j) {
      const gp_Pnt2d uv(u0 + (u1 - u0) * i / nu, v0 + (v1 - v0) * j / nv);
      surface.D0(uv.X(), uv.Y(), S);
      xyz.push_back(to_vec(S));
      grid->uv.push_back(uv);
    }
  grid->locator = std::make_unique<PointLocator>(xyz);
  return grid;
}

// Whether uv is a foot point of p (the first-order conditions of the nearest point within the
// surface's parameter bounds): the offset r = p - S(u, v) orthogonal to the surface along each
// free parameter, and along one held at a bound pointing out of the bounds (the distance would
// fall only past it). local_foot declares a point settled once a halved step moves it by next
// to nothing, which Gauss-Newton's steps do on the concave side of a tight bend (inside a
// thread's tube) short of the foot point, and stops at a corner where the joint step points
// out of both bounds, which a skewed parameterization does short of the border's foot point.
bool stationary(ShapeAnalysis_Surface& analyser, const gp_Pnt& p, const gp_Pnt2d& uv) {
  const Handle(GeomAdaptor_Surface)& surface = analyser.Adaptor3d();
  double u0, u1, v0, v1;
  analyser.Bounds(u0, u1, v0, v1);
  gp_Pnt S;
  gp_Vec Su, Sv;
  surface->D1(uv.X(), uv.Y(), S, Su, Sv);
  const gp_Vec r(S, p);
  const double scale = r.Magnitude();
  if (scale < 1e-300) return true;
  auto holds = [&](double x, double lo, double hi, bool periodic, const gp_Vec& d) {
    const double slope = r.Dot(d), eps = 1e-6 * scale * d.Magnitude();  // -d|r|^2/dx / 2
    if (!periodic && x <= lo) return slope <= eps;
    if (!periodic && x >= hi) return slope >= -eps;
    return std::abs(slope) <= eps;
  };
  return holds(uv.X(), u0, u1, surface->IsUPeriodic(), Su) && holds(uv.Y(), v0, v1, surface->IsVPeriodic(), Sv);
}

// The (u, v) of the start grid's sample nearest p (false: the face has none, or its surface
// is elementary: a plane, cylinder, cone, sphere or torus, whose global search OCCT solves in
// closed form, faster than any start grid).
bool nearest_start(const BrepSource::Impl& s, Index face, ShapeAnalysis_Surface& analyser, const Vec3& p,
                   gp_Pnt2d& uv) {
  switch (analyser.Adaptor3d()->GetType()) {
    case GeomAbs_Plane: case GeomAbs_Cylinder: case GeomAbs_Cone: case GeomAbs_Sphere: case GeomAbs_Torus:
      return false;
    default:
      break;
  }
  BrepSource::Impl::StartGrids& grids = *s.start_grids;
  std::call_once(grids.once[face], [&] {
    try {
      grids.grid[face] = start_grid(s.face(face), *analyser.Adaptor3d());
    } catch (const Standard_Failure&) {
      grids.grid[face] = std::make_unique<BrepSource::Impl::StartGrid>();
    }
  });
  const auto& grid = grids.grid[face];
  if (!grid || !grid->locator || grid->locator->empty()) return false;
  uv = grid->uv[grid->locator->nearest(p)];
  return true;
}

}  // namespace

Vec3 BrepSource::project_to_face(Index face, const Vec3& p, double* distance, double near, bool* inside) const {
  const Impl& s = *impl_;
  ShapeAnalysis_Surface& analyser = s.analyser(face);
  auto size_of = [&](Index f) {
    if (s.face_size[f] <= 0) s.face_size[f] = std::max(face_bounding_box(f).diagonal(), 1e-300);
    return s.face_size[f];
  };
  Vec3 q = p;
  if (inside) *inside = true;
  try {
    gp_Pnt2d uv;
    // A local answer settled on the surface's border is taken only close by
    // (a tenth of `near`): farther off, another part of a curved face may be
    // nearer than the border (one sample in 8,000 on handle.step's crease
    // neighbours), which only the global search sees.
    bool on_border = false;
    bool local = near > 0 && s.has_last_uv[face] &&
                 local_foot(analyser, to_pnt(p), s.last_uv[face], size_of(face), uv, on_border) &&
                 analyser.Value(uv).Distance(to_pnt(p)) <= (on_border ? 0.1 * near : near);
    // Without a warm start (near 0: the nearest point of the whole part, asked of every face
    // whose box is near enough), the search starts at the face's start-grid sample nearest p
    // (start_grid): the foot it settles on is no farther than that sample, in the basin of the
    // face's nearest part, so the answer is the global search's but where two parts of one
    // face lie almost equally near. That holds for a foot on the surface's border too (a point
    // beside the face): unlike a warm start's, this start lies in the face's nearest part.
    // OCCT's global search samples a grid of the whole surface per point and then projects
    // onto its isolines: on a threaded screw 190,000 such searches took most of a two-minute fit.
    gp_Pnt2d start;
    if (!local && near == 0 && nearest_start(s, face, analyser, p, start))
      local = local_foot(analyser, to_pnt(p), start, size_of(face), uv, on_border) &&
              stationary(analyser, to_pnt(p), uv);
    if (!local) uv = s.global_uv(face, to_pnt(p));
    s.last_uv[face] = uv, s.has_last_uv[face] = 1;
    q = to_vec(analyser.Value(uv));
    if (inside) *inside = s.inside_trim(face, analyser.Surface(), uv);
  } catch (const Standard_Failure&) {
  }
  if (distance) *distance = (q - p).norm();
  return q;
}

std::string BrepSource::to_brep_string() const {
  std::ostringstream out;
  BRepTools::Write(impl_->shape, out);
  return out.str();
}

bool is_brep_file(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".step" || ext == ".stp" || ext == ".iges" || ext == ".igs" || ext == ".brep" || ext == ".brp";
}

}  // namespace stripweave
