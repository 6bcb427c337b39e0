// Strip compatibility (paper §6.2): the g' nodes a strip disables.
//
// incompatible_nodes(graph, strip, max_angle_deg) -> node ids
//   Inside a strip's area (the vertices of its triangles), a g' node whose
//   departure direction lies within max_angle_deg (45 by default) of the
//   strip's isocurves runs along the strip. Disabling such nodes makes every
//   later loop cross the strip transversally, and no loop topologically
//   equivalent to the strip's own is proposed again.
//   The set is closed under reversal (a node is disabled together with its
//   reversed node): the mask stays symmetric, so a loop and its reversed copy
//   are still both allowed or both forbidden.
//   Returned sorted, without repeats.
#pragma once

#include "stripweave/elastica/elastica_graph.h"
#include "stripweave/strips/strip_extraction.h"

namespace stripweave {

std::vector<Index> incompatible_nodes(const Surface& surface, const ElasticaGraph& graph, const Strip& strip,
                                      double max_angle_deg = 45.0);

}  // namespace stripweave
