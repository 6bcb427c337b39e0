// Bindings of the symmetry maps and their detection (paper §5.8; issue 21).
// Symmetries cross as design.md's dicts, in MODEL units:
//   {"kind": "reflection", "point": [x,y,z], "normal": [..]}
//   {"kind": "rotation", "point": [x,y,z], "axis": [..], "order": n}
// plus "rms_error", "max_error" (model units) where measured.
//
// detect_symmetries(surface, tolerance=1e-3, max_order=12) -> [dict]
//   symmetry/detect_symmetries.h; tolerance in diagonals; "source": "detected".
// measure_symmetry(surface, dict) -> dict: the same symmetry (unit direction)
//   with its rms_error and max_error on the surface (symmetry_error.h).
// anchor_images(surface, dict, anchor) -> [[x,y,z(,dx,dy,dz)], ...]: the
//   anchor's images under psi^1 .. psi^(n-1), re-projected (anchor_images.h).
// axis_points(surface, dict) -> [{"point", "normal", "cap_radius"}]: where a
//   rotation's axis meets the surface (axis_seeds.h), model units.
// axis_seeds(surface, dict, fractions) -> per clearance fraction, the anchors
//   [[x,y,z,dx,dy,dz], ...] of one loop beside every such point (axis_seed).
// symmetric_surface(surface, dict, sector_start=[]) -> Surface: the solver
//   mesh made exactly symmetric under a reflection or a rotation
//   (symmetric_surface.h, rotation_surface.h; a rotation's sector from
//   sector_start when given).
// map_points(dict, points, k=1) -> (n, 3) array: psi^k of the points.
// image_distance(dict, k, a, b) -> one-sided distance of psi^k(a) from the
//   polyline b (image_distance.h), model units.
#include "bind.h"

#include "stripweave/core/error.h"
#include "stripweave/symmetry/anchor_images.h"
#include "stripweave/symmetry/axis_seeds.h"
#include "stripweave/symmetry/detect_symmetries.h"
#include "stripweave/symmetry/image_distance.h"
#include "stripweave/symmetry/rotation_surface.h"
#include "stripweave/symmetry/symmetric_surface.h"
#include "stripweave/symmetry/symmetry_error.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

namespace {

Vec3 vector_of(const py::dict& d, const char* key) {
  if (!d.contains(key)) throw InputError(std::string("a symmetry needs '") + key + "'");
  std::vector<double> v;
  try {
    v = d[key].cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw InputError(std::string("a symmetry's '") + key + "' must be three numbers");
  }
  if (v.size() != 3) throw InputError(std::string("a symmetry's '") + key + "' must be three numbers");
  return Vec3(v[0], v[1], v[2]);
}

std::vector<double> list3(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

Symmetry normalized_symmetry(const Surface& s, Symmetry sym) {
  sym.point = s.similarity.to_normalized(sym.point);
  return sym;
}

py::dict symmetry_dict(const Surface& s, const Symmetry& sym) {
  py::dict d;
  const bool reflection = sym.kind == SymmetryKind::Reflection;
  d["kind"] = reflection ? "reflection" : "rotation";
  d["point"] = list3(s.similarity.to_model(sym.point));
  d[reflection ? "normal" : "axis"] = list3(sym.direction);
  if (!reflection) d["order"] = sym.order;
  d["rms_error"] = sym.rms_error * s.similarity.scale;
  d["max_error"] = sym.max_error * s.similarity.scale;
  return d;
}

Symmetry symmetry_of(const py::dict& d) {
  const std::string kind = d.contains("kind") ? py::str(d["kind"]).cast<std::string>() : "";
  if (kind == "reflection") return Symmetry::reflection(vector_of(d, "point"), vector_of(d, "normal"));
  if (kind == "rotation") {
    if (!d.contains("order")) throw InputError("a rotation needs 'order'");
    int order = 0;
    try {
      order = d["order"].cast<int>();
    } catch (const py::cast_error&) {
      throw InputError("a rotation's 'order' must be a whole number");
    }
    return Symmetry::rotation(vector_of(d, "point"), vector_of(d, "axis"), order);
  }
  throw InputError("a symmetry's kind must be 'reflection' or 'rotation', got '" + kind + "'");
}

void bind_symmetry(py::module_& m) {
  m.def("detect_symmetries", [](const Surface& s, double tolerance, int max_order) {
        SymmetryOptions options;
        options.tolerance = tolerance;
        options.max_order = max_order;
        std::vector<Symmetry> found;
        {
          py::gil_scoped_release release;
          found = detect_symmetries(s, options);
        }
        py::list out;
        for (const Symmetry& sym : found) {
          py::dict d = symmetry_dict(s, sym);
          d["source"] = "detected";
          out.append(d);
        }
        return out;
      }, py::arg("surface"), py::arg("tolerance") = 1e-3, py::arg("max_order") = 12,
      "The surface's reflections and rotations within tolerance (diagonals), model units");

  m.def("measure_symmetry", [](const Surface& s, const py::dict& d) {
        Symmetry sym = normalized_symmetry(s, symmetry_of(d));
        {
          py::gil_scoped_release release;
          const SurfaceLocator locator(s.mesh);
          const SymmetryError e = symmetry_error(sym, s.mesh.positions, locator);
          sym.rms_error = e.rms;
          sym.max_error = e.max;
        }
        py::dict out = symmetry_dict(s, sym);
        if (d.contains("source")) out["source"] = d["source"];
        return out;
      }, py::arg("surface"), py::arg("symmetry"), "The symmetry with its RMS and max error on the surface");

  m.def("anchor_images", [](const Surface& s, const py::dict& d, const std::vector<double>& a) {
        const Symmetry sym = normalized_symmetry(s, symmetry_of(d));
        const Anchor anchor = anchor_from(s, a);
        const SurfaceLocator locator(s.mesh);
        py::list out;
        for (const Anchor& image : anchor_images(sym, anchor, s.mesh, locator)) {
          std::vector<double> v = list3(s.similarity.to_model(image.point));
          if (image.directional()) v.insert(v.end(), image.direction.data(), image.direction.data() + 3);
          out.append(v);
        }
        return out;
      }, py::arg("surface"), py::arg("symmetry"), py::arg("anchor"),
      "The anchor's images on the other parts, re-projected onto the surface");

  m.def("axis_points", [](const Surface& s, const py::dict& d) {
        const Symmetry sym = normalized_symmetry(s, symmetry_of(d));
        py::list out;
        for (const AxisPoint& p : axis_points(s, sym)) {
          py::dict x;
          x["point"] = list3(s.similarity.to_model(p.point));
          x["normal"] = list3(p.normal);
          x["cap_radius"] = p.cap_radius * s.similarity.scale;
          out.append(x);
        }
        return out;
      }, py::arg("surface"), py::arg("symmetry"), "Where a rotation's axis meets the surface, model units");

  m.def("axis_seeds", [](const Surface& s, const py::dict& d, const std::vector<double>& fractions) {
        const Symmetry sym = normalized_symmetry(s, symmetry_of(d));
        if (sym.kind != SymmetryKind::Rotation) throw InputError("axis seeds need a rotation");
        std::vector<std::vector<Anchor>> seeds;
        {
          py::gil_scoped_release release;
          const std::vector<AxisPoint> points = axis_points(s, sym);
          const SurfaceLocator locator(s.mesh);
          for (double f : fractions) seeds.push_back(axis_seed(s, sym, points, f, locator));
        }
        py::list out;
        for (const std::vector<Anchor>& seed : seeds) {
          py::list anchors;
          for (const Anchor& a : seed) {
            std::vector<double> v = list3(s.similarity.to_model(a.point));
            v.insert(v.end(), a.direction.data(), a.direction.data() + 3);
            anchors.append(v);
          }
          out.append(anchors);
        }
        return out;
      }, py::arg("surface"), py::arg("symmetry"), py::arg("fractions"),
      "Per clearance fraction, the anchors of one loop beside every point where the rotation's axis meets the surface");

  m.def("symmetric_surface", [](const Surface& s, const py::dict& d, const std::vector<double>& sector_start) {
        const Symmetry sym = normalized_symmetry(s, symmetry_of(d));
        if (!sector_start.empty() && (sector_start.size() != 3 || sym.kind != SymmetryKind::Rotation))
          throw InputError("a sector start is three numbers, for a rotation");
        const std::optional<Vec3> start =
            sector_start.empty() ? std::nullopt : std::optional<Vec3>(Vec3(sector_start[0], sector_start[1], sector_start[2]));
        py::gil_scoped_release release;
        if (start) return std::make_shared<Surface>(rotation_symmetric_surface(s, sym, start));
        return std::make_shared<Surface>(symmetric_surface(s, sym));
      }, py::arg("surface"), py::arg("symmetry"), py::arg("sector_start") = std::vector<double>{},
      "The surface with its solver mesh made exactly symmetric under the reflection (one half mirrored) "
      "or the rotation (one sector turned n times; sector_start: the direction across the axis where the "
      "sector starts, else where the cut is quietest)");

  m.def("map_points", [](const py::dict& d, const py::handle& points, int k) {
        const Symmetry sym = symmetry_of(d);
        const std::vector<Vec3> p = points_from(points, "points");
        py::array_t<double> out({static_cast<py::ssize_t>(p.size()), static_cast<py::ssize_t>(3)});
        auto a = out.mutable_unchecked<2>();
        for (std::size_t i = 0; i < p.size(); ++i) {
          const Vec3 q = sym.map_point(p[i], k);
          for (int j = 0; j < 3; ++j) a(i, j) = q[j];
        }
        return out;
      }, py::arg("symmetry"), py::arg("points"), py::arg("k") = 1, "psi^k of the points");

  m.def("image_distance", [](const py::dict& d, int k, const py::handle& a, const py::handle& b) {
        return image_distance(symmetry_of(d), k, points_from(a, "a"), points_from(b, "b"));
      }, py::arg("symmetry"), py::arg("k"), py::arg("a"), py::arg("b"),
      "The largest distance from psi^k of polyline a to polyline b");
}

}  // namespace stripweave_python
