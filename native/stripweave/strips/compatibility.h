// Strip compatibility (paper §6.2): the g' nodes a strip disables.
//
// incompatible_nodes(surface, graph, strip, loop, max_angle_deg, band) -> node ids
//   Inside a strip's area (the vertices of its triangles), a g' node whose
//   departure direction lies within max_angle_deg (45 by default) of the
//   strip's isocurves runs along the strip. Disabling such nodes makes every
//   later loop cross the strip transversally, and no loop topologically
//   equivalent to the strip's own is proposed again.
//   The set is closed under reversal (a node is disabled together with its
//   reversed node): the mask stays symmetric, so a loop and its reversed copy
//   are still both allowed or both forbidden.
//   band (model units, as Strip::coords, default unbounded): only where the strip lies
//   within this distance of its loop (|across| <= band at a corner of the
//   vertex's covered triangles). The paper disables the whole strip; a
//   bounded band lets a denser layout put parallel loops further away.
//   loop: the strip's loop. A g-edge can also cross the loop between its
//   two ends, with no node near it (where the strip is narrow, stopped by a
//   nearby singularity, a g-edge spans it): a curve through that edge meets
//   the loop at the edge's own angle, and within max_angle_deg the
//   parameterization would have to make both curves isocurves of the same
//   coordinate and refuses the design. Such edges are disabled as well,
//   wherever the strip reaches.
//   Where the strip does not cover its own loop (no width there, or a band
//   narrower than a triangle), the corners of the triangles the loop runs
//   through disable the nodes within max_angle_deg of the loop's direction:
//   a later loop may cross it but never run along it through its vertices,
//   which the parameterization refuses (contradicting_meetings), whatever
//   the strip's width.
//   Returned sorted, without repeats.
#pragma once

#include "stripweave/elastica/elastica_graph.h"
#include "stripweave/strips/strip_extraction.h"

#include <limits>

namespace stripweave {

std::vector<Index> incompatible_nodes(const Surface& surface, const ElasticaGraph& graph, const Strip& strip,
                                      const LoopPath& loop, double max_angle_deg = 45.0,
                                      double band = std::numeric_limits<double>::infinity());

}  // namespace stripweave
