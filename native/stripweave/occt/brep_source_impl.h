// BrepSource::Impl: the OCCT side of a BrepSource (occt/ internal; shared by
// the files that define BrepSource's queries: brep_source.cpp and
// brep_dense_samples.cpp). Per-face caches are mutable and per instance: a
// thread uses its own BrepSource::thread_copy().
#pragma once

#include "stripweave/cgal/point_locator.h"
#include "stripweave/occt/brep_source.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <Extrema_ExtPC.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <Geom_Surface.hxx>
#include <gp_Pnt2d.hxx>

#include <algorithm>
#include <array>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace stripweave {

struct BrepSource::Impl {
  TopoDS_Shape shape;
  TopTools_IndexedMapOfShape faces, edges, vertices;
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
  // Per face, lazily (analyser()). OCCT's global search (ShapeAnalysis_Surface::ValueOfUV)
  // keeps a grid of the surface in its analyser, tens to hundreds of KB on a B-spline face,
  // and an assembly of 618 faces, asked from two threads, held 400 MB of them at the refit's
  // peak (the deviation's second look asks every face near a badly fitted sample). So at
  // most kSearchGrids analysers that searched a non-elementary surface are kept
  // (global_uv(): the least recently searched goes, and is rebuilt alike when asked again:
  // no answer changes); one that has not costs little, and stays.
  static constexpr Index kSearchGrids = 64;
  mutable std::vector<std::unique_ptr<ShapeAnalysis_Surface>> analysers;
  mutable std::vector<std::uint64_t> searched_at;  // per face, the clock at its last search; 0: no grid held
  mutable std::uint64_t search_clock = 0;
  mutable Index held_grids = 0;
  ShapeAnalysis_Surface& analyser(Index f) const;
  gp_Pnt2d global_uv(Index f, const gp_Pnt& p) const;
  mutable std::vector<gp_Pnt2d> last_uv;        // per face, the previous project_to_face answer
  mutable std::vector<std::uint8_t> has_last_uv;
  mutable std::vector<std::unique_ptr<BRepTopAdaptor_FClass2d>> classifiers;  // per face, lazily
  mutable std::vector<std::unique_ptr<BRepAdaptor_Surface>> adaptors;  // per face, lazily (foot_on_face)
  mutable std::vector<std::array<double, 4>> uv_box;                   // per face with an adaptor: u0, u1, v0, v1
  // Per edge, lazily (project_to_edge): its curve adaptor and the point-curve
  // extremum search set up on it once. A fresh adaptor and search per query
  // (handle copies, the curve's set-up) cost two thirds of the fit's time on
  // a B-rep part whose samples near creases are projected onto every edge.
  struct EdgeCurve {
    explicit EdgeCurve(const TopoDS_Edge& e) : curve(e) {
      extrema.Initialize(curve, curve.FirstParameter(), curve.LastParameter());
    }
    BRepAdaptor_Curve curve;
    Extrema_ExtPC extrema;  // keeps a pointer to curve: an EdgeCurve never moves
  };
  mutable std::vector<std::unique_ptr<EdgeCurve>> edge_curves;
  mutable std::vector<double> face_size;  // per face, its box diagonal, lazily (0: not yet; project_to_face)
  // Per face, lazily: the start grid of a cold foot-point search (brep_source.cpp's
  // start_grid), its samples' (u, v) and a locator of the nearest; null locator: none. The
  // grids depend on the face alone, so an instance and its thread copies share them (built
  // once, under a once_flag per face, then only read): the deviation's second look makes
  // copies anew for every measurement, and rebuilding the grids made a refit slower.
  struct StartGrid {
    std::vector<gp_Pnt2d> uv;
    std::unique_ptr<PointLocator> locator;
  };
  struct StartGrids {
    explicit StartGrids(size_t faces) : once(faces), grid(faces) {}
    std::vector<std::once_flag> once;
    std::vector<std::unique_ptr<StartGrid>> grid;
  };
  std::shared_ptr<StartGrids> start_grids;
  std::vector<std::string> warnings;                                   // repairs made on reading (sewing)

  explicit Impl(const TopoDS_Shape& s) : shape(s) {
    TopExp::MapShapes(shape, TopAbs_FACE, faces);
    TopExp::MapShapes(shape, TopAbs_EDGE, edges);
    TopExp::MapShapes(shape, TopAbs_VERTEX, vertices);
    TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edge_faces);
    analysers.resize(faces.Extent());
    searched_at.assign(faces.Extent(), 0);
    last_uv.resize(faces.Extent());
    has_last_uv.assign(faces.Extent(), 0);
    classifiers.resize(faces.Extent());
    adaptors.resize(faces.Extent());
    uv_box.resize(faces.Extent());
    face_size.assign(faces.Extent(), 0.0);
    edge_curves.resize(edges.Extent());
    start_grids = std::make_shared<StartGrids>(faces.Extent());
  }
  const TopoDS_Face& face(Index i) const { return TopoDS::Face(faces(i + 1)); }
  const TopoDS_Edge& edge(Index i) const { return TopoDS::Edge(edges(i + 1)); }

  // Distinct faces around an edge (a seam lists its face twice).
  std::vector<Index> faces_of_edge(Index e) const {
    std::vector<Index> result;
    const Index k = edge_faces.FindIndex(edge(e));
    if (k == 0) return result;
    for (TopTools_ListIteratorOfListOfShape it(edge_faces(k)); it.More(); it.Next()) {
      const Index f = faces.FindIndex(it.Value()) - 1;
      if (std::find(result.begin(), result.end(), f) == result.end()) result.push_back(f);
    }
    return result;
  }
  // Whether (u, v) lies within the face's trim (the border counts as
  // inside); a periodic surface answers in its own period while the trim may
  // lie in the next one, so the neighbouring periods are tried too.
  bool inside_trim(Index f, const Handle(Geom_Surface)& surface, const gp_Pnt2d& uv) const {
    auto& classifier = classifiers[f];
    if (!classifier) classifier = std::make_unique<BRepTopAdaptor_FClass2d>(face(f), 1e-7);
    bool inside = classifier->Perform(uv) != TopAbs_OUT;
    for (int k = 0; k < 4 && !inside; ++k) {
      const bool along_u = k < 2;
      if (along_u ? !surface->IsUPeriodic() : !surface->IsVPeriodic()) continue;
      const double period = (k % 2 ? -1 : 1) * (along_u ? surface->UPeriod() : surface->VPeriod());
      const gp_Pnt2d shifted(uv.X() + (along_u ? period : 0), uv.Y() + (along_u ? 0 : period));
      inside = classifier->Perform(shifted) != TopAbs_OUT;
    }
    return inside;
  }
  Index edge_use_count(Index e) const {
    const Index k = edge_faces.FindIndex(edge(e));
    return k == 0 ? 0 : edge_faces(k).Extent();
  }
};

}  // namespace stripweave
