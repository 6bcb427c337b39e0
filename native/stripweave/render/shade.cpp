// Shading the preview pictures' pixels (see shade.h). The arithmetic follows
// the numpy shader it replaces step by step, so the pictures stay the same.
#include "stripweave/render/shade.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

std::vector<Vec3> shade(const RasterPixels& raster, const std::vector<Vec3>& vertices, const std::vector<Tri>& triangles,
                        const std::vector<Vec3>& normals, const ShadeLook& look) {
  // Per triangle its own unit normal (the same numbers per pixel, once).
  std::vector<Vec3> face(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Tri& f = triangles[t];
    const Vec3 n = (vertices[f[1]] - vertices[f[0]]).cross(vertices[f[2]] - vertices[f[0]]);
    face[t] = n / std::max(n.norm(), 1e-30);
  }
  std::vector<Vec3> out(raster.count, look.background);
  for (size_t p = 0; p < raster.count; ++p) {
    const Index t = raster.triangle[p];
    if (t < 0) continue;
    const Tri& f = triangles[t];
    const std::array<double, 3>& b = raster.bary[p];
    Vec3 n = normals[f[0]] * b[0] + normals[f[1]] * b[1] + normals[f[2]] * b[2];
    n /= std::max(n.norm(), 1e-12);
    if (std::abs(face[t].dot(n)) < 0.9) n = face[t];
    const double lambert = 0.35 + 0.65 * std::abs(n.dot(look.light));
    Vec3 base = look.base;
    if (!look.tint.empty() && !std::isnan(look.tint[t].x())) base = 0.45 * base + 0.55 * look.tint[t];
    Vec3 rgb = base * lambert;
    for (const ShadeStrip& s : look.strips) {
      const std::array<double, 3>& c = s.across[t];
      const double across = c[0] * b[0] + c[1] * b[1] + c[2] * b[2];
      if (std::isnan(across)) continue;
      const double x = across / look.stripe_period + 0.5;
      const double phase = std::abs((x - std::floor(x)) - 0.5);  // 0 on a stripe line
      const double line = std::clamp(1.6 - phase * 8.0, 0.0, 1.0) * look.stripe_strength;
      rgb = rgb * (1 - line) + s.hue * lambert * line;
    }
    out[p] = rgb;
  }
  return out;
}

}  // namespace stripweave
