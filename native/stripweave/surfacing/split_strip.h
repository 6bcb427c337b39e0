// split_strip: a patch no bicubic fits within tolerance, even at the most
// spans the fit allows, is split in two along an isoline of its square map;
// so that the network stays conforming (no T-junction), the split runs on
// through the whole dual strip the isoline crosses.
//
// Input   a PatchNetwork (patch_network.h) and a StripCut: a patch, a
//         direction (0: the isoline u = at, which crosses sides 0 and 2;
//         1: the isoline v = at, which crosses sides 1 and 3) and `at`
//         strictly inside (0, 1).
// Output  the network split in place, and a StripSplit saying what changed:
//         every patch of the strip is cut in two (the piece on the side of
//         smaller u (v) keeps its index, the other is appended), every edge
//         the cut crosses is split at a new vertex (its first half keeps the
//         index, the second is appended), and a new edge chain runs across
//         the strip, one edge per patch. An open strip splits its two end
//         edges on the boundary; a closed one closes on itself. Every new
//         vertex is a corner of every patch around it.
// Method  The strip is the chain of patches joined by opposite sides (the
//         classes of fit_patch_network's span counts). The square map pins
//         each side by normalized arc length, so the isoline u = c meets
//         side 0 and side 2 at arc-length fraction c from the u = 0 rail:
//         following the strip, the cut keeps one arc-length fraction on
//         every edge it crosses, measured from the same rail. Each edge is
//         cut once at that fraction (snapped to a polyline point within
//         1e-3), and both patches on it take the cut from the edge, so
//         their new corners are the same point. Inside each patch the
//         triangles are cut along the isoline of its own harmonic map
//         (patch_parameterization.h), linearly between the vertices, and
//         the pieces keep their triangles' source faces.
//         The strip is not split (the network is left as it was, why_not
//         says why) when it crosses itself (a patch crossed both ways, or
//         the cut comes back to a patch at another fraction: a twisted
//         strip), or a piece is not a quad disc.
#pragma once

#include "stripweave/surfacing/patch_network.h"

#include <string>

namespace stripweave {

struct StripCut {
  Index patch = kInvalid;
  int direction = 0;  // 0: u = at (across sides 0 and 2), 1: v = at (across sides 1 and 3)
  double at = 0.5;
};

struct StripSplit {
  bool done = false;
  std::string why_not;             // when not done
  std::vector<Index> patches;      // the strip's patches, in order along it (the first pieces)
  std::vector<Index> new_patches;  // the second piece of each, in the same order
  std::vector<Index> new_edges;    // the edge chain across the strip, one per patch, same order
  bool closed = false;             // the strip closes on itself (no boundary edge at its ends)
};

StripSplit split_strip(PatchNetwork& network, const StripCut& cut);

}  // namespace stripweave
