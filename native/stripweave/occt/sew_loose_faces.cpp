#include "stripweave/occt/sew_loose_faces.h"

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <ShapeFix_Solid.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Shell.hxx>

#include <cmath>
#include <sstream>

namespace stripweave {

namespace {

// Edges bounded by one face use (a seam is used twice by its face; a
// degenerate edge at a pole is no border).
int free_edge_count(const TopoDS_Shape& shape) {
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
  TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edge_faces);
  int free = 0;
  for (int i = 1; i <= edge_faces.Extent(); ++i)
    if (edge_faces(i).Extent() == 1 && !BRep_Tool::Degenerated(TopoDS::Edge(edge_faces.FindKey(i)))) ++free;
  return free;
}

double diagonal_of(const TopoDS_Shape& shape) {
  Bnd_Box box;
  BRepBndLib::Add(shape, box, /*useTriangulation=*/false);
  if (box.IsVoid()) return 0;
  return std::sqrt(box.SquareExtent());
}

// Closed shells as solids, oriented outward (sewing keeps the faces' own
// orientation, which an unsewn export need not have made consistent outward).
TopoDS_Shape solids_of_closed_shells(const TopoDS_Shape& sewn) {
  BRep_Builder builder;
  TopoDS_Compound out;
  builder.MakeCompound(out);
  bool changed = false;
  for (TopExp_Explorer ex(sewn, TopAbs_SHELL); ex.More(); ex.Next()) {
    const TopoDS_Shell& shell = TopoDS::Shell(ex.Current());
    if (BRep_Tool::IsClosed(shell)) {
      const TopoDS_Solid solid = ShapeFix_Solid().SolidFromShell(shell);
      if (!solid.IsNull()) {
        builder.Add(out, solid);
        changed = true;
        continue;
      }
    }
    builder.Add(out, shell);
  }
  // Faces the sewing left outside any shell stay as they are.
  for (TopExp_Explorer ex(sewn, TopAbs_FACE, TopAbs_SHELL); ex.More(); ex.Next()) builder.Add(out, ex.Current());
  return changed ? TopoDS_Shape(out) : sewn;
}

}  // namespace

TopoDS_Shape sew_loose_faces(const TopoDS_Shape& shape, std::vector<std::string>& warnings) {
  const int free_before = free_edge_count(shape);
  const double diagonal = diagonal_of(shape);
  if (free_before == 0 || !(diagonal > 0) || !std::isfinite(diagonal)) return shape;
  const double tolerance = kSewingTolerance * diagonal;
  TopoDS_Shape sewn;
  try {
    BRepBuilderAPI_Sewing sewing(tolerance);
    sewing.Add(shape);
    sewing.Perform();
    sewn = sewing.SewedShape();
    if (sewn.IsNull()) return shape;
    sewn = solids_of_closed_shells(sewn);
  } catch (const Standard_Failure&) {
    return shape;  // the shape as given: its free edges stay borders
  }
  const int free_after = free_edge_count(sewn);
  if (free_after >= free_before) return shape;
  std::ostringstream msg;
  msg << "sewed " << free_before - free_after << " of " << free_before
      << " free edges of loose faces into shared edges (tolerance " << tolerance << " model units, "
      << kSewingTolerance << " of the diagonal); " << free_after << " free edges remain";
  warnings.push_back(msg.str());
  return sewn;
}

}  // namespace stripweave
