// symmetric_fit: the fitted patch network made exactly symmetric under the
// part's accepted symmetries (paper §5.8, "fit on M0 and map"; issue 21).
//
// Pairing (pair_network): under a symmetry psi every layout vertex, edge and
// patch has an image: the vertex nearest psi(x) (within `tolerance`, model
// units, one-to-one), the edge between the images of its ends whose
// arc-length midpoint lies nearest the mapped midpoint (within `tolerance`,
// or a quarter of the edge's length if more: edges are routed over the
// mesh, which the symmetry does not map onto itself; one-to-one;
// `reversed` when psi(v0) is the image's v1), the patch whose four edges are
// the images of its four. The patch's sides map to the image's sides by a
// symmetry of the square: for a rotation (orientation kept) side s goes to
// side s + r running the same way, for a reflection (orientation reversed)
// to side r - s running backwards. An element may be its own image (an edge
// or patch across the mirror plane or around the axis).
// A pairing that fails anywhere fails whole (`paired` false, `problem` says
// where): the layout is not symmetric and the fit is left as it is.
//
// Spans: span counts are a property of a strip (fit_patch_network.h step 3);
// a strip and its image must have the same, so the fit unites them
// (strip_images: the edge pairs to unite).
//
// Symmetrizing (symmetrize_fit): each element's control net becomes the mean
// of its group's images of it, (1/n) sum_k psi^k(X[sigma^-k(x)]), with the
// control points re-indexed by the side map (uniform clamped knot vectors
// are symmetric, so reversing a direction reverses its control row). That is
// the representative's net mapped onto each image (fit once on M0, map), and
// for an element that is its own image the invariant mean with its mapped,
// re-indexed self. The group mean is an orthogonal projection, so several
// symmetries are applied in turn until the net is invariant under all.
// Edges first, then patches; the patches' boundary rows are then set to
// their edge curves' control points again, so the shell stays watertight.
//
// symmetry_error: the largest distance between an element's mapped control
// points and its image's (model units), over edges and patches.
#pragma once

#include "stripweave/surfacing/bspline.h"
#include "stripweave/surfacing/patch_network.h"
#include "stripweave/symmetry/symmetry.h"

#include <array>
#include <string>
#include <vector>

namespace stripweave {

struct NetworkPairing {
  bool paired = false;
  std::string problem;              // why not, in words
  std::vector<Index> vertex_image;  // per vertex
  std::vector<Index> edge_image;    // per edge
  std::vector<bool> edge_reversed;  // the image runs from psi(v1) to psi(v0)
  std::vector<Index> patch_image;   // per patch
  std::vector<int> side_shift;      // per patch: side s goes to side (shift + s) or (shift - s) mod 4
  bool reflection = false;          // the sides' order reverses (and each side's direction)
};

NetworkPairing pair_network(const PatchNetwork& network, const Symmetry& psi, double tolerance);

// The control nets mapped by psi onto their images (edge_curves and surfaces
// as fit_patch_network returns them); InputError when a net's size differs
// from its image's.
struct FitNets {
  std::vector<BSplineCurve3> edges;
  std::vector<BSplinePatch> patches;
};
FitNets map_nets(const FitNets& nets, const Symmetry& psi, const NetworkPairing& pairing);

double symmetry_error(const FitNets& nets, const PatchNetwork& network, const std::vector<Symmetry>& symmetries,
                      const std::vector<NetworkPairing>& pairings);

// Symmetrize under every paired symmetry (pairings[i] for symmetries[i]);
// returns the symmetry_error after.
double symmetrize_fit(FitNets& nets, const PatchNetwork& network, const std::vector<Symmetry>& symmetries,
                      const std::vector<NetworkPairing>& pairings, double diagonal);

}  // namespace stripweave
