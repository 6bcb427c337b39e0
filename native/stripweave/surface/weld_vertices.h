// weld_coincident: merge the vertices of a triangle soup that have identical
// coordinates (STL and many exporters store every triangle's corners apart).
//
// Input : a TriangleMesh with finite coordinates and valid indices.
// Output: the same triangles over one vertex per distinct position, numbered
//         in the order of each position's first vertex (the order a std::map
//         weld gave: results downstream do not change). -0.0 and 0.0 are one
//         coordinate; nothing is merged that is not exactly equal.
// O(n) expected: an open-addressing hash of the exact coordinates (the
// std::map weld took most of a million-triangle load).
#pragma once

#include "stripweave/surface/triangle_mesh.h"

namespace stripweave {

TriangleMesh weld_coincident(const TriangleMesh& raw);

}  // namespace stripweave
