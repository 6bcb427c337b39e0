// PatchNetwork: the primal quad layout as the surfacing stage consumes it
// (the hand-over from layout/ to surfacing/; no OCCT type here).
//
//   vertices   the layout's vertices (model units); shared exactly by the
//              edges that end there
//   edges      one per primal edge: a polyline on the surface from vertex
//              v0 to vertex v1 (points.front() == vertices[v0],
//              points.back() == vertices[v1]); `sharp` when it lies on a
//              sharp feature curve (C0 seam), `boundary` when it lies on the
//              open boundary (one patch only)
//   patches    one quad per loop crossing: its 4 sides in counter-clockwise
//              order seen from outside, side i being edge `edges[i]`, run
//              from v0 to v1 unless `reversed[i]`; and the surface piece it
//              covers as a triangle mesh (a disc, model units, counter-
//              clockwise from outside) whose boundary is exactly the 4 sides'
//              polylines: corners[i] is the patch-mesh vertex at the start of
//              side i, and the boundary from corners[i] to corners[i + 1]
//              (counter-clockwise) carries side i's points in order.
//              source_face: per patch triangle, the B-rep face it lies on
//              (kInvalid without a B-rep), so samples project to the exact
//              surface.
#pragma once

#include "stripweave/surface/triangle_mesh.h"

#include <array>

namespace stripweave {

struct NetworkEdge {
  std::vector<Vec3> points;
  Index v0 = kInvalid, v1 = kInvalid;
  bool sharp = false;
  bool boundary = false;
};

struct NetworkPatch {
  std::array<Index, 4> edges{kInvalid, kInvalid, kInvalid, kInvalid};
  std::array<bool, 4> reversed{false, false, false, false};
  TriangleMesh mesh;
  std::array<Index, 4> corners{kInvalid, kInvalid, kInvalid, kInvalid};
  std::vector<Index> source_face;
  // Its square map spreads its area evenly instead of being harmonic
  // (patch_parameterization.h): set by the fit for a patch whose harmonic
  // map squashes a protrusion; a split's pieces inherit it.
  bool even_stretch = false;
};

struct PatchNetwork {
  std::vector<Vec3> vertices;
  std::vector<NetworkEdge> edges;
  std::vector<NetworkPatch> patches;
  double bbox_diagonal = 1;  // of the model, for relative tolerances
};

}  // namespace stripweave
