// Creases: the ONE set of sharp edges every stage treats as a feature of the
// part (issue 17). The surface stage decides it once; afterwards a surface
// edge is a crease iff its class is EdgeClass::Feature, and the g' feature
// weights (§5.6), the cross-field constraints, the assessment and the layout
// all read that class. Sharp edges that are not creases (scan noise) are
// Regular everywhere.
//
// keep_crease_curves(mesh, topo, classes, curves, edge_curve)
//   Input : a mesh in normalized units (bounding-box diagonal 1), its edge
//           classes with every dihedral-sharp edge Feature, the feature
//           curves chained from them and edge_curve (feature_curves.h).
//   Rule  : a curve is a crease when it is at least kMinCreaseLength long and
//           its network (curves joined at their ends) holds a curve at least
//           kMinCreaseSpan long. Its edges stay Feature; the other curves'
//           edges become Regular and the curves are dropped (edge_curve
//           renumbered).
//   Why   : a part's creases run long between junctions (a CAD edge spans a
//           good part of the part), while scan noise forms networks of many
//           short chains joined at their ends; each junction of noise would
//           otherwise take a primal vertex as a "corner of the part", and its
//           ridges would pull loops and the field. The rule is in normalized
//           units, so it holds for parts of any size. tests/test_creases.py
//           checks it on generated noise ridges.
//   Meshes only: on a B-rep every sharp CAD edge is a crease (its sharpness is
//   exact, not measured from noise).
//
// creases_of(surface) -> per surface edge, 1 if it is a crease (its class is
//   Feature).
#pragma once

#include "stripweave/surface/surface.h"

#include <cstdint>

namespace stripweave {

constexpr double kMinCreaseLength = 0.03;
constexpr double kMinCreaseSpan = 0.1;
// A patch lies over a crease when more than this length of crease (normalized
// units: a fraction of the bounding-box diagonal) runs inside it; less is a
// nick at a corner that the fit absorbs. The layout (PrimalPatch::creased)
// and the refit (PatchFitFigures::creased) judge by this one figure.
constexpr double kCreasedPatchLength = 0.01;

void keep_crease_curves(const TriangleMesh& mesh, const MeshTopology& topo, std::vector<EdgeClass>& classes,
                        std::vector<FeatureCurve>& curves, std::vector<Index>& edge_curve);

std::vector<std::uint8_t> creases_of(const Surface& s);

}  // namespace stripweave
