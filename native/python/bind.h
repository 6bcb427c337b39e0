// The parts of the _stripweave module, one file per pipeline stage.
#pragma once

#include "stripweave/core/fp_guard.h"
#include "stripweave/elastica/loop_session.h"
#include "stripweave/symmetry/symmetry.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace stripweave_python {
// How a binding runs the core: the GIL released (a long computation must not
// freeze FreeCAD's GUI) and floating-point traps turned into an InputError
// (core/fp_guard.h: masked, and GMP's SIGFPE thrown), so that no native
// failure kills the process. The guard ends before the GIL is taken back.
struct NativeCall {
  pybind11::gil_scoped_release release;
  stripweave::FloatingPointGuard guard;
};
// Shared by the stage bindings (defined in bind_loops.cpp).
// An anchor as (x, y, z) or (x, y, z, dx, dy, dz) in model units.
// InputError for a non-finite point, one over 1e3 diagonals from the model, a zero direction.
stripweave::Anchor anchor_from(const stripweave::Surface& s, const std::vector<double>& a);
// InputError when two anchors of one chain sit at one point with different tangents.
void check_anchor_chain(const std::vector<stripweave::Anchor>& anchors);
// An embedded path as a dict: points (model units), vertex, edge, t, node_start, length.
pybind11::dict path_dict(const stripweave::Surface& s, const stripweave::SurfacePath& p);
// An (n, 3) array (or anything numpy turns into one) as points; InputError
// "<what> must be an (n, 3) array" otherwise.
std::vector<stripweave::Vec3> points_from(const pybind11::handle& a, const std::string& what);
// A symmetry from its design.md dict (defined in bind_symmetry.cpp), in the
// dict's units; InputError for a bad kind, vector or order.
stripweave::Symmetry symmetry_of(const pybind11::dict& d);
// A symmetry in model units taken to the surface's normalized units, and a
// normalized symmetry as its design.md dict in model units (with its errors).
stripweave::Symmetry normalized_symmetry(const stripweave::Surface& s, stripweave::Symmetry sym);
pybind11::dict symmetry_dict(const stripweave::Surface& s, const stripweave::Symmetry& sym);

// A vector handed to numpy without a copy: the array owns it and frees it with
// itself (a copy would double a supersampled picture's tens of MB for a moment).
// `shape`'s trailing sizes must fill one T with Elems.
template <class Elem, class T>
pybind11::array_t<Elem> array_owning(std::vector<T>&& values, std::vector<pybind11::ssize_t> shape) {
  static_assert(sizeof(T) % sizeof(Elem) == 0, "a T must hold whole Elems");
  auto* owned = new std::vector<T>(std::move(values));
  pybind11::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return pybind11::array_t<Elem>(shape, reinterpret_cast<const Elem*>(owned->data()), owner);
}

// Points as an (n, 3) array that owns them (array_owning).
inline pybind11::array_t<double> points_array(std::vector<stripweave::Vec3> points) {
  const auto n = static_cast<pybind11::ssize_t>(points.size());
  return array_owning<double>(std::move(points), {n, pybind11::ssize_t(3)});
}

void bind_loops(pybind11::module_& m);
void bind_field(pybind11::module_& m);   // cross field (paper §6.1)
void bind_param(pybind11::module_& m);   // global parameterization (§6.1)
void bind_design(pybind11::module_& m);  // designs, strips, compatibility (§4.1, §6)
void bind_regions(pybind11::module_& m);  // loop arrangement, regions, assessment (§4.2)
void bind_surfacing(pybind11::module_& m);  // patch network -> B-spline patches, shell, STEP
void bind_weave(pybind11::module_& m);    // automatic weaving: assessment and seed points (issue 6)
void bind_render(pybind11::module_& m);   // the preview pictures' rasterizer and shader
void bind_symmetry(pybind11::module_& m); // symmetry maps and their detection (§5.8)
}
