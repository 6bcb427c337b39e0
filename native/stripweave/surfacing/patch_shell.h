// Patch shell: the fitted B-spline patches as an OpenCASCADE shell or solid,
// and its STEP AP214 export (OCCT stays in the .cpp).
//
// Input   the fitted patches (each side exactly its shared edge curve), a
//         sewing tolerance (model units).
// Output  an opaque PatchShell holding the sewn shape, and ShellFigures:
//         faces, shells, free edges, closed, valid (BRepCheck_Analyzer),
//         volume (BRepGProp, closed input only), largest edge tolerance.
// Method  One Geom_BSplineSurface per patch (clamped uniform knots, degree 3
//         both ways) bounded by its natural boundary (BRepBuilderAPI_MakeFace);
//         the faces' boundaries coincide to rounding because neighbours
//         share their boundary control rows, so BRepBuilderAPI_Sewing with a
//         tiny tolerance merges them into shared edges. Every closed shell
//         becomes a solid (BRepBuilderAPI_MakeSolid), oriented outward by
//         ShapeFix_Solid: an assembly's solids stay one solid each, in one
//         compound with any open shells.
//
// write_step(shell, path, colours)  STEPCAFControl_Writer (an XDE document)
//     with write.step.schema = AP214IS: each patch's face named "patch i"
//     (its index among the fitted patches, as in the fit report's per_patch)
//     and, when colours are given (RGB in [0, 1] per patch), coloured; reads
//     the file back (STEPControl_Reader) and returns its face count.
//     InputError if the file cannot be written.
// to_brep_string(shell)  BRepTools::Write, for FreeCAD's
//     Part.Shape().importBrepFromString.
#pragma once

#include "stripweave/surfacing/bspline.h"

#include <memory>
#include <string>

namespace stripweave {

class PatchShell;

struct ShellFigures {
  Index faces = 0;
  Index shells = 0;
  Index free_edges = 0;
  Index solids = 0;           // closed shells made solids
  bool closed = false;        // every shell closed and made a solid
  bool valid = false;
  double volume = 0;          // model units cubed: the solids' sum
  double max_tolerance = 0;   // largest vertex/edge tolerance after sewing
};

std::shared_ptr<const PatchShell> sew_patch_shell(const std::vector<BSplinePatch>& patches, double sew_tolerance,
                                                  ShellFigures* figures);
Index write_step(const PatchShell& shell, const std::string& path, const std::vector<Vec3>& colours = {});
std::string to_brep_string(const PatchShell& shell);

}  // namespace stripweave
