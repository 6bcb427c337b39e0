// Rasterizing a triangle mesh for the preview pictures (issue 6).
//
// rasterize(screen, triangles, width, height) -> Raster
//   Input : per vertex its screen position (x, y) in pixels (x to the right,
//           y down, the image's top left corner at (0, 0)) and its depth
//           (smaller is nearer); triangles as vertex index triples; the
//           image size in pixels.
//   Output: per pixel (row-major, width * height) the nearest triangle whose
//           closed interior holds the pixel's centre (x + 0.5, y + 0.5), or
//           -1; that centre's barycentric coordinates in it; its depth
//           (infinity where no triangle is). Both orientations count (the
//           preview shades open surfaces from both sides); triangles of no
//           area are skipped. Equal depths go to the lower triangle index,
//           so the picture does not depend on the order of the work.
//
// Why native: the preview is part of every `weave` run, and the numpy
// rasterizer it replaces took 1.5 to 2.6 s of a 30 s budget on the shared
// models (2048 x 1536 pixels, 30K triangles); a scanline loop takes a few
// tens of milliseconds. It is display, not geometry: the picture shows what
// the other stages computed.
#pragma once

#include "stripweave/core/types.h"

#include <array>
#include <vector>

namespace stripweave {

struct Raster {
  int width = 0, height = 0;
  std::vector<Index> triangle;               // per pixel, -1 for none
  std::vector<std::array<double, 3>> bary;   // per pixel
  std::vector<double> depth;                 // per pixel, +infinity for none
};

// A raster's per-pixel arrays, read where they lie (the shader reads the
// caller's buffers: a copy of a supersampled view's raster is tens of MB).
struct RasterPixels {
  const Index* triangle = nullptr;
  const std::array<double, 3>* bary = nullptr;
  std::size_t count = 0;
};
inline RasterPixels pixels_of(const Raster& r) { return {r.triangle.data(), r.bary.data(), r.triangle.size()}; }

Raster rasterize(const std::vector<Vec3>& screen, const std::vector<Tri>& triangles, int width,
                 int height);

}  // namespace stripweave
