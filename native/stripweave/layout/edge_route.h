// A primal edge routed by hand (paper §7, manual: the user decides "where
// within a dual loop corridor a patch boundary should lie"): the edge whose
// arc passes nearest `across` goes through `through` (normalized units).
// A layout input kept with the design, like the vertex pins; the rules are
// in primal_edge_routes.cpp.
#pragma once

#include "stripweave/core/types.h"

namespace stripweave {

struct EdgeRoute {
  Vec3 through = Vec3::Zero();
  Vec3 across = Vec3::Zero();
};

}  // namespace stripweave
