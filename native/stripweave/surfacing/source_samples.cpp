#include "stripweave/surfacing/source_samples.h"

#include <algorithm>
#include <cmath>

namespace stripweave {

namespace {

void sample_triangle(const Vec3& a, const Vec3& b, const Vec3& c, double spacing, SourceSamples& out) {
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  const int n = std::clamp(static_cast<int>(std::ceil(longest / spacing)), 1, 64);
  const double area = 0.5 * (b - a).cross(c - a).norm() / (double(n) * n);
  auto at = [&](double i, double j) { return Vec3(a + (i / n) * (b - a) + (j / n) * (c - a)); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      out.points.push_back(at(i + 1.0 / 3, j + 1.0 / 3));  // "up" sub-triangle's centroid
      out.area.push_back(area);
      if (i + j + 2 <= n) {
        out.points.push_back(at(i + 2.0 / 3, j + 2.0 / 3));  // "down"
        out.area.push_back(area);
      }
    }
}

}  // namespace

SourceSamples sample_source(const Surface& surface, double spacing, double chord) {
  if (surface.brep) return surface.brep->dense_samples(spacing, chord);
  SourceSamples out;
  if (surface.source_mesh && surface.source_mesh->num_triangles() > 0) {
    out.mesh = *surface.source_mesh;
  } else {
    out.mesh = surface.mesh;
    for (Vec3& p : out.mesh.positions) p = surface.similarity.to_model(p);
  }
  const TriangleMesh& m = out.mesh;
  for (const Tri& t : m.triangles) sample_triangle(m.positions[t[0]], m.positions[t[1]], m.positions[t[2]], spacing, out);
  return out;
}

}  // namespace stripweave
