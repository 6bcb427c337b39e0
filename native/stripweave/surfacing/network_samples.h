// network_samples: step 2 of fit_patch_network.h, the fit's samples on the
// exact source.
//
// Input   the PatchNetwork and its NetworkTopology, each patch's
//         square map (updated where a patch's border moves, below), the
//         SourceProjector (the B-rep, or the mesh), FitOptions (edge_density,
//         edge_smoothing, progress), the SampleMemo of the fits before.
// Output  NetworkSamples:
//         - per patch-mesh vertex, the source faces of the triangles around it
//           (a B-rep source whose patch knows its triangles' faces);
//         - per network edge, its densified polyline projected onto the
//           source (edge_curves.h), smoothed on smooth seams;
//         - per patch whose border runs along a smoothed edge, its mesh with
//           the border moved onto the smoothed samples and the two rings
//           inside relaxed onto the source, and its square map redone (else
//           the map pins the zig-zag mesh path to the square's side while the
//           edge curve runs smooth, up to half a mesh edge away, and the fit
//           answers with ripples);
//         - per patch, one sample per mesh vertex, triangle centroid and edge
//           midpoint, projected onto the source, with its (u, v).
//         smooth_vertex_normals: the source's normal at the network vertices
//         where only smooth seams meet (the edge curves' end tangents).
// Method  Patches are projected side by side, each thread through a
//         projector of its own (the B-rep's caches are per thread), each
//         patch and edge from no warm start and in breadth-first order over
//         its mesh (consecutive projections are neighbours, so the local
//         Newton from the previous foot point converges): the samples do not
//         depend on which thread took which patch, and a patch or edge an
//         earlier fit of the same call sampled is taken from the memo.
#pragma once

#include "stripweave/surfacing/edge_curves.h"
#include "stripweave/surfacing/fit_patch_network.h"
#include "stripweave/surfacing/network_topology.h"
#include "stripweave/surfacing/patch_fit.h"
#include "stripweave/surfacing/patch_parameterization.h"
#include "stripweave/surfacing/sample_memo.h"
#include "stripweave/surfacing/source_projection.h"

#include <vector>

namespace stripweave {

struct NetworkSamples {
  std::vector<std::vector<std::vector<Index>>> vertex_faces;  // per patch, per mesh vertex: source faces around it
  std::vector<EdgeSamples> edges;                             // per network edge
  std::vector<bool> edge_smoothed;                            // per network edge: a smoothed smooth seam
  std::vector<TriangleMesh> moved;                            // per patch: its mesh with the border moved, or empty
  std::vector<PatchSamples> patches;                          // per patch

  // The patch mesh the samples were taken on.
  const TriangleMesh& mesh(const PatchNetwork& network, Index p) const {
    return moved[p].num_vertices() ? moved[p] : network.patches[p].mesh;
  }
};

NetworkSamples sample_network(const PatchNetwork& network, const NetworkTopology& topology,
                              std::vector<PatchParameterization>& param, const SourceProjector& projector,
                              const FitOptions& options, SampleMemo& memo);

// Per network vertex where every edge is a smooth seam between two patches,
// the unit surface normal there: the source's exact normal where there is a
// B-rep, else the area-weighted mean of the patch-mesh triangles around the
// corners there; zero elsewhere (a sharp or boundary vertex, where the
// patches need not share a normal).
std::vector<Vec3> smooth_vertex_normals(const PatchNetwork& network, const NetworkTopology& topology,
                                        const NetworkSamples& samples, const SourceProjector& projector);

}  // namespace stripweave
