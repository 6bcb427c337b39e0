// zipper_fill: close a hole of a welded tessellation without fins.
//
// zipper_fill(loop, positions) -> triangles
//   Input : a boundary loop (vertex ids in the order the triangles beside it
//           run along it) and the mesh's vertex positions.
//   Output: triangles that close it, running against the loop (so that the
//           closed mesh is consistently oriented); loop.size() - 2 of them
//           for a simple loop.
//   How   : the two loop vertices farthest apart split the loop into two
//           chains, which a zipper joins: each step advances the chain whose
//           next vertex is nearer the other's current one. A gap between two
//           polylines of one curve (a B-rep curve discretized twice, or a face
//           BRepMesh could not mesh) becomes a strip whose every diagonal joins
//           the two sides. A fan from one vertex joined that vertex to others
//           of its own side, where the neighbours' triangles may already have
//           an edge: a fin of three triangles (bug32596_abc_0_13).
//   Cost  : quadratic in the loop's length (the farthest pair), linear after.
#pragma once

#include "stripweave/core/types.h"

#include <vector>

namespace stripweave {

std::vector<Tri> zipper_fill(const std::vector<Index>& loop, const std::vector<Vec3>& positions);

}  // namespace stripweave
