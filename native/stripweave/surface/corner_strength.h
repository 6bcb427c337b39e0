// corner_strength(surface, crease) -> per surface vertex, how much of a
//   corner it is (0 if none), in radians, given per surface edge whether it
//   is a crease the layout follows (creases_of, creases.h: B-rep edges and
//   feature curves long enough to be real, not scan noise):
//     on the open boundary  the boundary's turn |pi - angle sum| where it
//                           exceeds kCornerTurn (30 degrees); where a crease
//                           ends on it (the end of a square tube: the
//                           boundary does not turn within the surface
//                           there, but the part has a corner), that turn,
//                           at least 1e-3;
//     inside                where three or more creases meet, the angle
//                           defect |2 pi - angle sum| (a cube corner's
//                           pi/2), at least 1e-3 so that a flat junction
//                           still counts.
//   A corner is where a CAD engineer expects a patch corner: the primal
//   vertices go there (primal_vertices.cpp). Dual curves keep their ends
//   away from the crease ends among them (loop_search.cpp).
#pragma once

#include "stripweave/surface/surface.h"

namespace stripweave {

constexpr double kCornerTurn = 30.0 * M_PI / 180.0;

std::vector<double> corner_strength(const Surface& s, const std::vector<std::uint8_t>& crease);

}  // namespace stripweave
