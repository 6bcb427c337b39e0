// creases_of(surface) -> per surface edge, whether it is a crease: a sharp
// feature edge of a B-rep, or of a mesh's feature curve at least
// kMinCreaseLength long in a network (curves joined at their ends) whose
// longest curve is at least kMinCreaseSpan long (normalized units:
// fractions of the bounding-box diagonal). The layout pins primal vertices and edges to creases, and
// their junctions and ends on the boundary are corners (corner_strength.h).
// Why the length: on a scan, the feature curves are mostly short chains of
// scan noise joined into networks (the rocker-arm: 281 of 291 curves
// shorter than 0.05, the median 0.01; camelhead and spot alike; fandisk's
// median is 0.3), and every junction of three of them took a primal vertex
// as a "corner of the part", wherever in its region it lay: corners of 3 to
// 20 degrees next to the loops, 30 to 40 degrees mean at such vertices
// against 17 at centred ones. The surface keeps them (they may be real, and
// the field and the loops weigh them only softly); the layout, which pins
// vertices and edges to creases, needs creases that are surely real.
// Why the span: the length alone kept a scan's longer noise curves, and
// they are joined into networks of many short ones (the rocker-arm's
// largest: 43 curves, none longer than 0.044; its longest curve anywhere
// 0.08), where a CAD mesh's creases run long between junctions (fandisk:
// one network, its longest curve 0.73). On the rocker-arm such ridges took
// primal vertices whose edges ran along them together (corners of 2, 24,
// 177 and 179 degrees), and automatic weaving ended at 19.1 degrees mean
// deviation with 45 patches; without them, 13.7 with 54. Curves of 0.1 and
// more stay (camelhead's single curves of 0.1 to 0.2, fertility's networks
// around curves of 0.11 and 0.16).
// (The loop search's rule against curves ending at crease ends,
// loop_tables in loop_search.cpp, still takes every feature edge.)
#pragma once

#include "stripweave/surface/surface.h"

#include <cstdint>

namespace stripweave {

constexpr double kMinCreaseLength = 0.03;
constexpr double kMinCreaseSpan = 0.1;
std::vector<std::uint8_t> creases_of(const Surface& s);

}  // namespace stripweave
