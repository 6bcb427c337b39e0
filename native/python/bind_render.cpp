// Bindings of the preview's rasterizer (render/rasterize.h).
//
// rasterize(screen, triangles, width, height) -> (triangle, bary, depth)
//   screen (n, 3) floats: pixel x, pixel y (down), depth (smaller is nearer);
//   triangles (m, 3) ints. Per pixel, row-major: the nearest triangle (int32,
//   -1 for none), its barycentrics (width * height, 3), the depth (+inf for
//   none). Errors: InputError for arrays of the wrong shape or a triangle
//   naming a vertex that does not exist.
// shade(triangle, bary, vertices, normals, triangles, light, base, background,
//       tints=None, stripes=[], hues=[], stripe_period=1, stripe_strength=0.6)
//       -> (pixels, 3) RGB
//   The pixels of rasterize's output shaded (render/shade.h): tints (m, 3)
//   per triangle with NaN rows for none; stripes, per strip, its stripe
//   coordinates per triangle corner (m, 3, 2: along, across; NaN outside; or
//   (m, 3): across alone, all the shader reads),
//   with hues, one RGB per strip; stripe_strength in [0, 1], the stripe line's
//   share of the colour.
#include "bind.h"

#include "stripweave/core/error.h"
#include "stripweave/render/rasterize.h"
#include "stripweave/render/shade.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

namespace {

using Floats = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Ints = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;
using Pixels = py::array_t<Index, py::array::c_style | py::array::forcecast>;  // rasterize's triangle per pixel

// An (m, 3) array of vertex indices as triangles, each naming one of `vertices`.
std::vector<Tri> triangles_from(const Ints& a, size_t vertices, const std::string& fn) {
  if (a.ndim() != 2 || a.shape(1) != 3) throw InputError(fn + ": triangles must be an (m, 3) array");
  const auto t = a.unchecked<2>();
  std::vector<Tri> out(static_cast<size_t>(t.shape(0)));
  for (py::ssize_t i = 0; i < t.shape(0); ++i)
    for (int k = 0; k < 3; ++k) {
      if (t(i, k) < 0 || t(i, k) >= static_cast<py::ssize_t>(vertices))
        throw InputError(fn + ": triangle " + std::to_string(i) + " names vertex " + std::to_string(t(i, k)) +
                         ", which does not exist");
      out[i][k] = static_cast<Index>(t(i, k));
    }
  return out;
}

Vec3 vec3(const std::vector<double>& v, const char* what) {
  if (v.size() != 3) throw InputError(std::string("shade: ") + what + " must have three components");
  return Vec3(v[0], v[1], v[2]);
}

}  // namespace

void bind_render(py::module_& m) {
  m.def(
      "rasterize",
      [](const Floats& screen, const Ints& triangles, int width, int height) {
        const std::vector<Vec3> points = points_from(screen, "rasterize: screen positions");
        const std::vector<Tri> tris = triangles_from(triangles, points.size(), "rasterize");
        if (width < 0 || height < 0) throw InputError("rasterize: the image size must not be negative");
        Raster r;
        {
          stripweave_python::NativeCall release;
          r = rasterize(points, tris, width, height);
        }
        const py::ssize_t n = static_cast<py::ssize_t>(r.triangle.size());
        // Handed over, not copied: the arrays own the raster's buffers.
        auto tri = array_owning<Index>(std::move(r.triangle), {n});
        auto bary = array_owning<double>(std::move(r.bary), {n, static_cast<py::ssize_t>(3)});
        auto depth = array_owning<double>(std::move(r.depth), {n});
        return py::make_tuple(tri, bary, depth);
      },
      py::arg("screen"), py::arg("triangles"), py::arg("width"), py::arg("height"),
      "Per pixel the nearest triangle (-1 for none), its barycentrics and the depth (render/rasterize.h)");

  m.def(
      "shade",
      [](const Pixels& triangle, const Floats& bary, const Floats& vertices, const Floats& normals, const Ints& triangles,
         const std::vector<double>& light,
         const std::vector<double>& base, const std::vector<double>& background, py::object tints,
         const std::vector<Floats>& stripes, const std::vector<std::vector<double>>& hues, double stripe_period,
         double stripe_strength) {
        ShadeLook look;
        look.light = vec3(light, "the light");
        look.base = vec3(base, "the base colour");
        look.background = vec3(background, "the background");
        if (!(stripe_period > 0)) throw InputError("shade: the stripe period must be positive");
        look.stripe_period = stripe_period;
        if (!(stripe_strength >= 0 && stripe_strength <= 1)) throw InputError("shade: the stripe strength must be in [0, 1]");
        look.stripe_strength = stripe_strength;
        const std::vector<Vec3> points = points_from(vertices, "shade: vertices");
        const std::vector<Vec3> vertex_normals = points_from(normals, "shade: normals");
        if (vertex_normals.size() != points.size()) throw InputError("shade: one normal per vertex is needed");
        const std::vector<Tri> tris = triangles_from(triangles, points.size(), "shade");
        const py::ssize_t nt = static_cast<py::ssize_t>(tris.size());
        if (!tints.is_none()) {
          look.tint = points_from(tints, "shade: tints");
          if (static_cast<py::ssize_t>(look.tint.size()) != nt) throw InputError("shade: one tint per triangle is needed");
        }
        if (hues.size() != stripes.size()) throw InputError("shade: one hue per strip is needed");
        for (size_t i = 0; i < stripes.size(); ++i) {
          const Floats& c = stripes[i];
          const bool across_only = c.ndim() == 2 && c.shape(0) == nt && c.shape(1) == 3;
          if (!across_only && (c.ndim() != 3 || c.shape(0) != nt || c.shape(1) != 3 || c.shape(2) != 2))
            throw InputError("shade: strip " + std::to_string(i) +
                             "'s coordinates must be a (triangles, 3, 2) array, or (triangles, 3) across alone");
          ShadeStrip strip;
          strip.hue = vec3(hues[i], "a hue");
          strip.across.resize(static_cast<size_t>(nt));
          const double* x = c.data();
          const int stride = across_only ? 1 : 2, at = across_only ? 0 : 1;  // C order: (t, corner[, along|across])
          for (py::ssize_t t = 0; t < nt; ++t)
            for (int k = 0; k < 3; ++k) strip.across[t][k] = x[(3 * t + k) * stride + at];
          look.strips.push_back(std::move(strip));
        }
        if (triangle.ndim() != 1 || bary.ndim() != 2 || bary.shape(1) != 3 || bary.shape(0) != triangle.shape(0))
          throw InputError("shade: triangle (pixels) and bary (pixels, 3) must come from one raster");
        // The pixels are read where numpy holds them (bary (n, 3) C-contiguous doubles is
        // laid out as std::array<double, 3> per pixel): no copy of the raster.
        const py::ssize_t n = triangle.shape(0);
        const auto ti = triangle.unchecked<1>();
        for (py::ssize_t i = 0; i < n; ++i)
          if (ti(i) >= nt) throw InputError("shade: a pixel names triangle " + std::to_string(ti(i)) + ", which does not exist");
        RasterPixels raster;
        raster.triangle = triangle.data();
        raster.bary = reinterpret_cast<const std::array<double, 3>*>(bary.data());
        raster.count = static_cast<size_t>(n);
        std::vector<Vec3> rgb;
        {
          stripweave_python::NativeCall release;
          rgb = shade(raster, points, tris, vertex_normals, look);
        }
        return array_owning<double>(std::move(rgb), {n, static_cast<py::ssize_t>(3)});
      },
      py::arg("triangle"), py::arg("bary"), py::arg("vertices"), py::arg("normals"), py::arg("triangles"),
      py::arg("light"), py::arg("base"), py::arg("background"), py::arg("tints") = py::none(),
      py::arg("stripes") = py::list(), py::arg("hues") = py::list(),
      py::arg("stripe_period") = 1.0, py::arg("stripe_strength") = 0.6, "RGB per pixel of a raster (render/shade.h)");
}

}  // namespace stripweave_python
