#include "stripweave/surfacing/patch_shell.h"

#include "stripweave/core/error.h"
#include "stripweave/occt/occt_messages.h"

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Controller.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <ShapeFix_Solid.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TCollection_ExtendedString.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <sstream>

namespace stripweave {

class PatchShell {
 public:
  TopoDS_Shape shape;
  std::vector<TopoDS_Face> faces;  // per fitted patch, its face in `shape` (after sewing)
};

namespace {

// Knots and multiplicities of the clamped uniform cubic knot vector.
void uniform_knots(int spans, TColStd_Array1OfReal& knots, TColStd_Array1OfInteger& mults) {
  for (int k = 0; k <= spans; ++k) {
    knots(k + 1) = double(k) / spans;
    mults(k + 1) = (k == 0 || k == spans) ? kSplineDegree + 1 : 1;
  }
}

Handle(Geom_BSplineSurface) to_occt(const BSplinePatch& p) {
  TColgp_Array2OfPnt poles(1, p.rows(), 1, p.cols());
  for (int i = 0; i < p.rows(); ++i)
    for (int j = 0; j < p.cols(); ++j) {
      const Vec3& c = p.P(i, j);
      poles(i + 1, j + 1) = gp_Pnt(c.x(), c.y(), c.z());
    }
  TColStd_Array1OfReal uk(1, p.nu + 1), vk(1, p.nv + 1);
  TColStd_Array1OfInteger um(1, p.nu + 1), vm(1, p.nv + 1);
  uniform_knots(p.nu, uk, um);
  uniform_knots(p.nv, vk, vm);
  return new Geom_BSplineSurface(poles, uk, vk, um, vm, kSplineDegree, kSplineDegree);
}

Index count_faces(const TopoDS_Shape& s) {
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(s, TopAbs_FACE, faces);
  return faces.Extent();
}

// The solid a closed shell bounds, oriented outward (ShapeFix_Solid, then
// reversed if its volume comes out negative); null if OCCT cannot make one.
TopoDS_Shape solid_of(const TopoDS_Shell& shell, double& volume) {
  BRepBuilderAPI_MakeSolid make(shell);
  if (!make.IsDone()) return TopoDS_Shape();
  ShapeFix_Solid fix(make.Solid());
  fix.Perform();
  TopoDS_Shape solid = fix.Solid();
  GProp_GProps props;
  BRepGProp::VolumeProperties(solid, props);
  if (props.Mass() < 0) {  // inside out: turn it
    solid.Reverse();
    BRepGProp::VolumeProperties(solid, props);
  }
  volume = props.Mass();
  return solid;
}

}  // namespace

std::shared_ptr<const PatchShell> sew_patch_shell(const std::vector<BSplinePatch>& patches, double sew_tolerance,
                                                  ShellFigures* figures) {
  auto out = std::make_shared<PatchShell>();
  ShellFigures fig;
  try {
    BRepBuilderAPI_Sewing sewing(sew_tolerance);
    for (const BSplinePatch& p : patches) {
      BRepBuilderAPI_MakeFace face(to_occt(p), Precision::Confusion());
      if (!face.IsDone()) throw InputError("could not make a face of a fitted patch");
      sewing.Add(face.Face());
      out->faces.push_back(face.Face());
    }
    sewing.Perform();
    // Each patch's face as the sewing left it (its name and colour in the STEP follow it;
    // making solids below only orients the shells, which keeps every face the same).
    for (TopoDS_Face& f : out->faces)
      if (sewing.IsModified(f)) f = TopoDS::Face(sewing.Modified(f));
    TopoDS_Shape sewn = sewing.SewedShape();
    fig.free_edges = sewing.NbFreeEdges();

    std::vector<TopoDS_Shell> shells;
    for (TopExp_Explorer ex(sewn, TopAbs_SHELL); ex.More(); ex.Next()) shells.push_back(TopoDS::Shell(ex.Current()));
    fig.shells = static_cast<Index>(shells.size());
    // One solid per closed shell (an assembly's solids are separate shells), the
    // open shells as they are.
    std::vector<TopoDS_Shape> parts;
    for (const TopoDS_Shell& shell : shells) {
      double volume = 0;
      const TopoDS_Shape solid = BRep_Tool::IsClosed(shell) ? solid_of(shell, volume) : TopoDS_Shape();
      if (solid.IsNull()) {
        parts.push_back(shell);
        continue;
      }
      parts.push_back(solid);
      fig.volume += volume;
      ++fig.solids;
    }
    fig.closed = !shells.empty() && fig.free_edges == 0 && fig.solids == fig.shells;
    if (parts.size() == 1) {
      sewn = parts.front();
    } else if (!parts.empty()) {
      TopoDS_Compound compound;
      BRep_Builder builder;
      builder.MakeCompound(compound);
      for (const TopoDS_Shape& part : parts) builder.Add(compound, part);
      sewn = compound;
    }
    out->shape = sewn;
    fig.faces = count_faces(sewn);
    fig.valid = BRepCheck_Analyzer(sewn).IsValid();
    for (TopExp_Explorer ex(sewn, TopAbs_EDGE); ex.More(); ex.Next())
      fig.max_tolerance = std::max(fig.max_tolerance, BRep_Tool::Tolerance(TopoDS::Edge(ex.Current())));
    for (TopExp_Explorer ex(sewn, TopAbs_VERTEX); ex.More(); ex.Next())
      fig.max_tolerance = std::max(fig.max_tolerance, BRep_Tool::Tolerance(TopoDS::Vertex(ex.Current())));
  } catch (const Standard_Failure& e) {
    throw InputError(std::string("sewing the fitted patches failed: ") + e.GetMessageString());
  }
  if (figures) *figures = fig;
  return out;
}

Index write_step(const PatchShell& shell, const std::string& path, const std::vector<Vec3>& colours) {
  try {
    quiet_occt_messages();  // the writer prints its statistics on stdout (a mesh source read none before)
    // The schema is read when the writer's model is made: set it first.
    STEPControl_Controller::Init();
    STEPCAFControl_Controller::Init();  // defines the write.stepcaf.* parameters
    Interface_Static::SetCVal("write.step.schema", "AP214IS");
    // Faces named after their patch ("patch 7"), in the file's ADVANCED_FACE entities.
    Interface_Static::SetIVal("write.stepcaf.subshapes.name", 1);
    // An XDE document: the shape, each patch face a named (and coloured) sub-shape.
    Handle(TDocStd_Document) doc;
    XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
    Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
    Handle(XCAFDoc_ColorTool) paint = XCAFDoc_DocumentTool::ColorTool(doc->Main());
    const TDF_Label root = shapes->AddShape(shell.shape, false);
    for (size_t i = 0; i < shell.faces.size(); ++i) {
      TDF_Label face = shapes->AddSubShape(root, shell.faces[i]);
      if (face.IsNull()) continue;
      TDataStd_Name::Set(face, TCollection_ExtendedString(("patch " + std::to_string(i)).c_str()));
      if (i < colours.size())
        paint->SetColor(face, Quantity_Color(colours[i].x(), colours[i].y(), colours[i].z(), Quantity_TOC_sRGB),
                        XCAFDoc_ColorSurf);
    }
    STEPCAFControl_Writer writer;
    writer.SetColorMode(true);
    writer.SetNameMode(true);
    if (!writer.Transfer(doc, STEPControl_AsIs)) throw InputError("could not translate the patch shell to STEP");
    if (writer.Write(path.c_str()) != IFSelect_RetDone) throw InputError("cannot write STEP file '" + path + "'");
    XCAFApp_Application::GetApplication()->Close(doc);
    STEPControl_Reader reader;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) return 0;
    reader.TransferRoots();
    return count_faces(reader.OneShape());
  } catch (const Standard_Failure& e) {
    throw InputError(std::string("STEP export failed: ") + e.GetMessageString());
  }
}

std::string to_brep_string(const PatchShell& shell) {
  std::ostringstream out;
  BRepTools::Write(shell.shape, out);
  return out.str();
}

}  // namespace stripweave
