// Shading the preview pictures' pixels (issue 6).
//
// shade(raster, mesh, normals, look) -> per pixel RGB in [0, 1]
//   Input : a raster of the mesh (its pixels: RasterPixels, rasterize.h); per vertex normals; what to
//           draw (ShadeLook): the light direction, the base colour, per
//           triangle a tint (NaN where none), per strip its stripe
//           coordinates (per triangle corner, the coordinate across the
//           strip; NaN outside it) with the strip's hue, the stripe period
//           (same units as the coordinates) and the background colour.
//   Output: row-major, one RGB per pixel:
//     Lambert, two-sided (0.35 + 0.65 |n . light|), with n the normal
//     interpolated from the vertices, or the triangle's own normal where the
//     two differ by more than acos(0.9) (at a crease the vertex normals
//     average across it and would blur the edge a CAD user expects);
//     the base colour, mixed 45:55 with the triangle's tint where it has one;
//     per strip covering the triangle, a stripe line where the coordinate
//     across is a multiple of the period (`stripe_strength`, by default 0.6,
//     of the strip's hue, shaded, fading out over an eighth of a period; the
//     preview dims them so the patch edges drawn over them stay the most
//     visible thing);
//     the background where no triangle is.
// The numpy shader it replaces (the same arithmetic) took 1.3 to 2.4 s of a
// weave run on 2048 x 1536 pixels.
#pragma once

#include "stripweave/render/rasterize.h"

namespace stripweave {

struct ShadeStrip {
  std::vector<std::array<double, 3>> across;  // per triangle corner; NaN outside the strip
  Vec3 hue = Vec3::Zero();
};

struct ShadeLook {
  Vec3 light = Vec3::UnitZ();               // unit
  Vec3 base = Vec3::Constant(0.8);
  Vec3 background = Vec3::Ones();
  std::vector<Vec3> tint;                   // per triangle, or empty; NaN for none
  std::vector<ShadeStrip> strips;
  double stripe_period = 1.0;
  double stripe_strength = 0.6;             // in [0, 1]: the stripe line's share of the colour
};

std::vector<Vec3> shade(const RasterPixels& raster, const std::vector<Vec3>& vertices, const std::vector<Tri>& triangles,
                        const std::vector<Vec3>& normals, const ShadeLook& look);
inline std::vector<Vec3> shade(const Raster& raster, const std::vector<Vec3>& vertices,
                               const std::vector<Tri>& triangles, const std::vector<Vec3>& normals,
                               const ShadeLook& look) {
  return shade(pixels_of(raster), vertices, triangles, normals, look);
}

}  // namespace stripweave
