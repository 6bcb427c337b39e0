// network_topology: who lies next to whom in a patch network, checked once
// for the whole surfacing stage.
//
// Input   a PatchNetwork.
// Output  NetworkTopology: per network edge the patch sides that run along
//         it (at most two: a seam, or one on the boundary), per patch the
//         patches sharing a vertex with it (where a sample by the border
//         may find its nearest surface).
// Errors  InputError: an edge naming a vertex that does not exist, an edge
//         of fewer than two points, a side naming an edge that does not
//         exist, an edge bounding more than two patch sides.
#pragma once

#include "stripweave/surfacing/patch_network.h"

#include <string>
#include <vector>

namespace stripweave {

// Side `side` of patch `patch` runs along an edge; `reversed` when it runs
// it from v1 to v0.
struct SideUse {
  Index patch = kInvalid;
  int side = 0;
  bool reversed = false;
};

struct NetworkTopology {
  std::vector<std::vector<SideUse>> uses;      // per edge, the patch sides along it
  std::vector<std::vector<Index>> neighbours;  // per patch, the others sharing a vertex with it, sorted
};

NetworkTopology network_topology(const PatchNetwork& network);

// "side s of patch p", for messages.
std::string side_name(Index patch, int side);

}  // namespace stripweave
