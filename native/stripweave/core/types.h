// Basic numeric types shared by every stage.
//
// Elements are addressed by 32-bit indices (`Index`): meshes of the sizes we
// design on (tens to hundreds of thousands of triangles) fit easily, and the
// elastica graph (about 60 |V| nodes) halves its memory against 64-bit ids.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <vector>

namespace stripweave {

using Index = std::int32_t;
constexpr Index kInvalid = -1;

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

// A triangle as three vertex indices, counter-clockwise seen from outside.
using Tri = std::array<Index, 3>;

// An undirected mesh edge as its two vertex indices, smaller first.
using EdgeKey = std::array<Index, 2>;

inline EdgeKey edge_key(Index a, Index b) { return a < b ? EdgeKey{a, b} : EdgeKey{b, a}; }

}  // namespace stripweave
