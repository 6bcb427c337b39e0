// Rasterizing a triangle mesh for the preview pictures (rasterize.h).
//
// Per triangle, the pixels of its bounding box are tested with the edge
// functions at their centres (the same test as the numpy version it
// replaces, so the pictures agree), and a pixel keeps the nearest sample.
#include "stripweave/render/rasterize.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace stripweave {

Raster rasterize(const std::vector<Vec3>& screen, const std::vector<Tri>& triangles, int width, int height) {
  Raster r;
  r.width = std::max(width, 0);
  r.height = std::max(height, 0);
  const size_t pixels = static_cast<size_t>(r.width) * static_cast<size_t>(r.height);
  r.triangle.assign(pixels, -1);
  r.bary.assign(pixels, {0.0, 0.0, 0.0});
  r.depth.assign(pixels, std::numeric_limits<double>::infinity());
  const Index n = static_cast<Index>(screen.size());
  for (Index t = 0; t < static_cast<Index>(triangles.size()); ++t) {
    const Tri& f = triangles[t];
    if (f[0] < 0 || f[1] < 0 || f[2] < 0 || f[0] >= n || f[1] >= n || f[2] >= n) continue;
    const Vec3 &a = screen[f[0]], &b = screen[f[1]], &c = screen[f[2]];
    const double area = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (!(std::abs(area) > 1e-12)) continue;  // no area, or not finite
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int x1 = std::min(r.width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y1 = std::min(r.height - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    const double inv = 1.0 / area;
    for (int y = y0; y <= y1; ++y) {
      const double sy = y + 0.5;
      for (int x = x0; x <= x1; ++x) {
        const double sx = x + 0.5;
        const double w0 = ((b.x() - sx) * (c.y() - sy) - (c.x() - sx) * (b.y() - sy)) * inv;
        const double w1 = ((c.x() - sx) * (a.y() - sy) - (a.x() - sx) * (c.y() - sy)) * inv;
        const double w2 = 1.0 - w0 - w1;
        if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9) continue;
        const double z = w0 * a.z() + w1 * b.z() + w2 * c.z();
        const size_t p = static_cast<size_t>(y) * static_cast<size_t>(r.width) + static_cast<size_t>(x);
        // Nearer wins; at equal depth the lower triangle index, which came first.
        if (z < r.depth[p]) {
          r.depth[p] = z;
          r.triangle[p] = t;
          r.bary[p] = {w0, w1, w2};
        }
      }
    }
  }
  return r;
}

}  // namespace stripweave
