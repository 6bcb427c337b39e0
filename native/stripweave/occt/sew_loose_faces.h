// Sewing loose faces back into shells (occt/ internal; used by BrepSource).
//
// An IGES or STEP exported unsewn (every face with edges of its own, e.g. a
// box as 6 loose faces or 12 single-face shells) has only free edges: no
// creases, no shared borders, every face a component of its own, and
// weaving then found nothing to do yet reported "valid" with 0 patches.
//
// sew_loose_faces(shape, warnings)
//   Input: any shape. When it has free edges (bounded by one face, not a
//   seam or a degenerate edge), BRepBuilderAPI_Sewing joins those that
//   coincide within kSewingTolerance of the shape's bounding-box diagonal;
//   closed shells it makes become solids oriented outward (ShapeFix_Solid).
//   Output: the sewn shape, with one warning line saying how many free edges
//   were sewn, when that made fewer free edges; otherwise the shape as given
//   (an open sheet's real boundary stays free and nothing is said).
#pragma once

#include <TopoDS_Shape.hxx>

#include <string>
#include <vector>

namespace stripweave {

// Of the bounding-box diagonal: gaps this small are an exporter's rounding,
// never a part's design (0.01 mm on a 100 mm part).
constexpr double kSewingTolerance = 1e-4;

TopoDS_Shape sew_loose_faces(const TopoDS_Shape& shape, std::vector<std::string>& warnings);

}  // namespace stripweave
