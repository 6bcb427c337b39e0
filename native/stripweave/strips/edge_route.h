// A primal edge routed by hand (paper §7, manual: the user decides "where
// within a dual loop corridor a patch boundary should lie"): the edge whose
// arc passes nearest `across` goes through `through` (normalized units).
// A layout input kept with the design (design_state.h), like the vertex
// pins; the layout stage reads it (quad_layout.h) and its rules are in
// layout/primal_edge_routes.cpp. It lives with the design so that the
// strips stage does not include the layout stage's headers.
#pragma once

#include "stripweave/core/types.h"

namespace stripweave {

struct EdgeRoute {
  Vec3 through = Vec3::Zero();
  Vec3 across = Vec3::Zero();
};

}  // namespace stripweave
