// Bindings of the preview's rasterizer (render/rasterize.h).
//
// rasterize(screen, triangles, width, height) -> (triangle, bary, depth)
//   screen (n, 3) floats: pixel x, pixel y (down), depth (smaller is nearer);
//   triangles (m, 3) ints. Per pixel, row-major: the nearest triangle (int64,
//   -1 for none), its barycentrics (width * height, 3), the depth (+inf for
//   none). Errors: InputError for arrays of the wrong shape or a triangle
//   naming a vertex that does not exist.
#include "bind.h"

#include "stripweave/core/error.h"
#include "stripweave/render/rasterize.h"

#include <pybind11/numpy.h>

#include <string>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

void bind_render(py::module_& m) {
  m.def(
      "rasterize",
      [](py::array_t<double, py::array::c_style | py::array::forcecast> screen,
         py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> triangles, int width, int height) {
        if (screen.ndim() != 2 || screen.shape(1) != 3)
          throw InputError("rasterize: screen positions must be an (n, 3) array");
        if (triangles.ndim() != 2 || triangles.shape(1) != 3)
          throw InputError("rasterize: triangles must be an (m, 3) array");
        if (width < 0 || height < 0) throw InputError("rasterize: the image size must not be negative");
        const auto s = screen.unchecked<2>();
        const auto t = triangles.unchecked<2>();
        std::vector<Vec3> points(static_cast<size_t>(s.shape(0)));
        for (py::ssize_t i = 0; i < s.shape(0); ++i) points[i] = Vec3(s(i, 0), s(i, 1), s(i, 2));
        std::vector<Tri> tris(static_cast<size_t>(t.shape(0)));
        for (py::ssize_t i = 0; i < t.shape(0); ++i) {
          for (int k = 0; k < 3; ++k) {
            if (t(i, k) < 0 || t(i, k) >= s.shape(0))
              throw InputError("rasterize: triangle " + std::to_string(i) + " names vertex " +
                               std::to_string(t(i, k)) + ", which does not exist");
            tris[i][k] = static_cast<Index>(t(i, k));
          }
        }
        Raster r;
        {
          py::gil_scoped_release release;
          r = rasterize(points, tris, width, height);
        }
        const py::ssize_t n = static_cast<py::ssize_t>(r.triangle.size());
        py::array_t<std::int64_t> tri(n);
        py::array_t<double> bary({n, static_cast<py::ssize_t>(3)});
        py::array_t<double> depth(n);
        auto ot = tri.mutable_unchecked<1>();
        auto ob = bary.mutable_unchecked<2>();
        auto od = depth.mutable_unchecked<1>();
        for (py::ssize_t i = 0; i < n; ++i) {
          ot(i) = r.triangle[i];
          for (int k = 0; k < 3; ++k) ob(i, k) = r.bary[i][k];
          od(i) = r.depth[i];
        }
        return py::make_tuple(tri, bary, depth);
      },
      py::arg("screen"), py::arg("triangles"), py::arg("width"), py::arg("height"),
      "Per pixel the nearest triangle (-1 for none), its barycentrics and the depth (render/rasterize.h)");
}

}  // namespace stripweave_python
