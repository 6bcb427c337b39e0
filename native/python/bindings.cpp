// _stripweave: thin pybind11 bindings of the native core.
//
// Conventions
//   - Everything returned to Python is in MODEL units (the core works on the
//     normalized model; conversion happens here, once).
//   - Long computations release the GIL, so a FreeCAD worker thread does not
//     freeze the GUI; they poll an optional Progress for cancellation.
//   - stripweave::InputError becomes _stripweave.InputError (a ValueError),
//     Cancelled becomes _stripweave.Cancelled.
#include "bind.h"
#include "stripweave/cgal/mesh_io.h"
#include "stripweave/core/error.h"
#include "stripweave/core/progress.h"
#include "stripweave/occt/brep_source.h"
#include "stripweave/surface/build_surface.h"
#include "stripweave/surface/creases.h"
#include "stripweave/surface/split_touching_edges.h"
#include "stripweave/surface/zipper_fill.h"
#include "stripweave/surface/surface_report.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;
using namespace stripweave;

namespace {

using Array3d = py::array_t<double, py::array::c_style | py::array::forcecast>;
// 64-bit on the way in: an index of 2**32 + k must be refused, not wrapped to k.
using Array3i = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

template <typename T, int N, typename F>
py::array_t<T> rows(Index count, F&& row) {
  py::array_t<T> out({static_cast<py::ssize_t>(count), static_cast<py::ssize_t>(N)});
  auto a = out.template mutable_unchecked<2>();
  for (Index i = 0; i < count; ++i) {
    const auto r = row(i);
    for (int j = 0; j < N; ++j) a(i, j) = static_cast<T>(r[j]);
  }
  return out;
}

template <typename T, typename F>
py::array_t<T> column(Index count, F&& value) {
  py::array_t<T> out(static_cast<py::ssize_t>(count));
  auto a = out.template mutable_unchecked<1>();
  for (Index i = 0; i < count; ++i) a(i) = static_cast<T>(value(i));
  return out;
}

py::array_t<std::int32_t> index_array(const std::vector<Index>& v) {
  return column<std::int32_t>(static_cast<Index>(v.size()), [&](Index i) { return v[i]; });
}

TriangleMesh mesh_from_arrays(const Array3d& vertices, const Array3i& triangles) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3)
    throw InputError("vertices must be an (N, 3) array of coordinates");
  if (triangles.ndim() != 2 || triangles.shape(1) != 3)
    throw InputError("triangles must be an (M, 3) array of vertex indices");
  TriangleMesh m;
  auto v = vertices.unchecked<2>();
  auto t = triangles.unchecked<2>();
  m.positions.reserve(v.shape(0));
  for (py::ssize_t i = 0; i < v.shape(0); ++i) m.positions.emplace_back(v(i, 0), v(i, 1), v(i, 2));
  m.triangles.reserve(t.shape(0));
  const std::int64_t n = v.shape(0);
  for (py::ssize_t i = 0; i < t.shape(0); ++i) {
    for (int j = 0; j < 3; ++j)
      if (t(i, j) < 0 || t(i, j) >= n)
        throw InputError("triangle " + std::to_string(i) + " refers to vertex " + std::to_string(t(i, j)) +
                         ", but the mesh has only " + std::to_string(n) + " vertices");
    m.triangles.push_back({static_cast<Index>(t(i, 0)), static_cast<Index>(t(i, 1)), static_cast<Index>(t(i, 2))});
  }
  return m;
}

py::dict report_dict(const Surface& s) {
  const SurfaceReport r = surface_report(s);
  py::dict d;
  d["vertices"] = r.vertices;
  d["triangles"] = r.triangles;
  d["components"] = r.components;
  d["genus"] = r.genus;
  d["boundary_loops"] = r.boundary_loops;
  d["feature_curves"] = r.feature_curves;
  d["feature_edges"] = r.feature_edges;
  d["brep_faces"] = r.brep_faces;
  d["bbox_diagonal"] = r.bbox_diagonal;
  d["warnings"] = r.warnings;
  return d;
}

py::array_t<double> model_points(const Surface& s, const std::vector<Index>& ids, bool close) {
  const Index n = static_cast<Index>(ids.size()) + (close && !ids.empty() ? 1 : 0);
  return rows<double, 3>(n, [&](Index i) {
    return Vec3(s.similarity.to_model(s.mesh.positions[ids[i % ids.size()]]));
  });
}

}  // namespace

PYBIND11_MODULE(_stripweave, m) {
  m.doc() = "StripWeave native core: Dual Strip Weaving (Campen & Kobbelt 2014) for quad layouts";

  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<Cancelled> cancelled(m, "Cancelled", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input_error.ptr(), e.what());
    } catch (const Cancelled& e) {
      PyErr_SetString(cancelled.ptr(), e.what());
    } catch (const py::builtin_exception&) {
      throw;  // pybind11's own (cast, index, stop iteration): its default translator raises them
    } catch (const py::error_already_set&) {
      throw;  // a Python error from a callback: raised as it was
    } catch (const std::bad_alloc&) {
      // No native failure may end the process (a macro would take FreeCAD down).
      PyErr_SetString(input_error.ptr(), "out of memory: the model or the options ask for more than this machine has");
    } catch (const std::exception& e) {
      PyErr_SetString(input_error.ptr(), (std::string("internal error in the native library: ") + e.what()).c_str());
    } catch (...) {
      PyErr_SetString(input_error.ptr(), "internal error in the native library (an unknown exception, e.g. OpenCASCADE's)");
    }
  });

  py::class_<Progress, std::shared_ptr<Progress>>(m, "Progress",
                                                  "Progress and cancellation of a running computation (thread-safe)")
      .def(py::init<>())
      .def("fraction", &Progress::fraction, "overall progress in [0, 1]")
      .def("stage", &Progress::stage_name, "name of the current stage")
      .def("cancel", &Progress::cancel, "ask the computation to stop; it raises Cancelled")
      .def("cancelled", &Progress::cancelled);

  py::class_<SurfaceOptions>(m, "SurfaceOptions")
      .def(py::init<>())
      .def_readwrite("deflection", &SurfaceOptions::deflection)
      .def_readwrite("relative_deflection", &SurfaceOptions::relative_deflection)
      .def_readwrite("angular_deflection_deg", &SurfaceOptions::angular_deflection_deg)
      .def_readwrite("target_triangles", &SurfaceOptions::target_triangles)
      .def_readwrite("feature_angle_deg", &SurfaceOptions::feature_angle_deg)
      .def_readwrite("min_feature_length", &SurfaceOptions::min_feature_length)
      .def_readwrite("curvature_radius", &SurfaceOptions::curvature_radius)
      .def_readwrite("remesh_iterations", &SurfaceOptions::remesh_iterations);

  py::class_<Surface, std::shared_ptr<Surface>>(m, "Surface", "The welded surface model (stage 1 of the pipeline)")
      .def("report", &report_dict, "the figures of `stripweave info`, in model units")
      .def_property_readonly("bbox_diagonal", [](const Surface& s) { return s.similarity.scale; })
      .def_property_readonly("center", [](const Surface& s) { return std::vector<double>(s.similarity.center.data(), s.similarity.center.data() + 3); })
      .def_property_readonly("vertices", [](const Surface& s) {
        return rows<double, 3>(s.mesh.num_vertices(), [&](Index v) { return Vec3(s.similarity.to_model(s.mesh.positions[v])); });
      }, "(N, 3) vertex positions, model units")
      .def_property_readonly("triangles", [](const Surface& s) {
        return rows<std::int32_t, 3>(s.mesh.num_triangles(), [&](Index t) { return s.mesh.triangles[t]; });
      }, "(M, 3) vertex indices, counter-clockwise seen from outside")
      .def_property_readonly("normals", [](const Surface& s) {
        return rows<double, 3>(s.mesh.num_vertices(), [&](Index v) { return s.normal[v]; });
      })
      .def_property_readonly("k_min", [](const Surface& s) {
        return column<double>(s.mesh.num_vertices(), [&](Index v) { return s.k_min[v] / s.similarity.scale; });
      }, "minimum principal curvature per vertex, 1/model units, positive where convex")
      .def_property_readonly("k_max", [](const Surface& s) {
        return column<double>(s.mesh.num_vertices(), [&](Index v) { return s.k_max[v] / s.similarity.scale; });
      })
      .def_property_readonly("d_min", [](const Surface& s) {
        return rows<double, 3>(s.mesh.num_vertices(), [&](Index v) { return s.d_min[v]; });
      })
      .def_property_readonly("d_max", [](const Surface& s) {
        return rows<double, 3>(s.mesh.num_vertices(), [&](Index v) { return s.d_max[v]; });
      })
      .def_property_readonly("source_face", [](const Surface& s) { return index_array(s.source_face); },
                             "per triangle, the 0-based source B-rep face (-1 for meshes)")
      .def_property_readonly("edges", [](const Surface& s) {
        return rows<std::int32_t, 2>(s.topology.num_edges(), [&](Index e) { return s.topology.edges[e]; });
      })
      .def_property_readonly("edge_class", [](const Surface& s) {
        return column<std::uint8_t>(s.topology.num_edges(), [&](Index e) { return static_cast<int>(s.edge_class[e]); });
      }, "per edge: 0 regular, 1 sharp feature, 2 open boundary")
      .def_property_readonly("creases", [](const Surface& s) {
        const std::vector<std::uint8_t> c = creases_of(s);
        return column<std::uint8_t>(s.topology.num_edges(), [&](Index e) { return static_cast<int>(c[e]); });
      }, "per edge: 1 where the layout follows a crease (surface/creases.h): every sharp edge of a B-rep, "
         "a mesh's sharp edges on long enough curves in a network with a long curve")
      .def_property_readonly("edge_curve", [](const Surface& s) { return index_array(s.edge_curve); })
      .def_property_readonly("feature_curves", [](const Surface& s) {
        py::list out;
        for (const auto& c : s.feature_curves) out.append(index_array(c.vertices));
        return out;
      }, "per feature curve, its chain of vertex ids")
      .def_property_readonly("feature_curve_closed", [](const Surface& s) {
        std::vector<bool> out;
        for (const auto& c : s.feature_curves) out.push_back(c.closed);
        return out;
      })
      .def_property_readonly("boundary_loops", [](const Surface& s) {
        py::list out;
        for (const auto& l : s.boundary_loops) out.append(index_array(l));
        return out;
      })
      .def("feature_curve_points", [](const Surface& s) {
        py::list out;
        for (const auto& c : s.feature_curves) out.append(model_points(s, c.vertices, c.closed));
        return out;
      }, "per feature curve, its polyline in model units (closed curves repeat their first point)")
      .def("boundary_loop_points", [](const Surface& s) {
        py::list out;
        for (const auto& l : s.boundary_loops) out.append(model_points(s, l, true));
        return out;
      })
      .def_property_readonly("timings_ms", [](const Surface& s) {
        py::dict d;
        for (const auto& [name, ms] : s.timings) d[py::str(name)] = ms;
        return d;
      }, "wall-clock milliseconds of each stage that built this surface, in order")
      .def_property_readonly("input_triangles", [](const Surface& s) { return s.input_triangles; },
                             "triangles of the tessellation or input mesh, before remeshing")
      .def_property_readonly("is_brep", [](const Surface& s) { return static_cast<bool>(s.brep); });

  m.def("load_file", [](const std::string& path, const SurfaceOptions& options, Progress* progress) {
        stripweave_python::NativeCall release;
        return std::make_shared<Surface>(load_surface(path, options, progress));
      }, py::arg("path"), py::arg("options") = SurfaceOptions(), py::arg("progress") = nullptr,
      "Build the surface model from a STEP/IGES/BREP or STL/OBJ/OFF/PLY file");

  m.def("from_brep_string", [](const std::string& text, const SurfaceOptions& options, Progress* progress) {
        stripweave_python::NativeCall release;
        return std::make_shared<Surface>(surface_from_brep(BrepSource::from_brep_string(text), options, progress));
      }, py::arg("brep"), py::arg("options") = SurfaceOptions(), py::arg("progress") = nullptr,
      "Build the surface model from a BREP string (Shape.exportBrepToString())");

  m.def("from_arrays", [](const Array3d& vertices, const Array3i& triangles, const SurfaceOptions& options,
                          Progress* progress) {
        TriangleMesh mesh = mesh_from_arrays(vertices, triangles);
        stripweave_python::NativeCall release;
        return std::make_shared<Surface>(surface_from_mesh(mesh, options, progress));
      }, py::arg("vertices"), py::arg("triangles"), py::arg("options") = SurfaceOptions(),
      py::arg("progress") = nullptr, "Build the surface model from (N,3) vertices and (M,3) triangles");

  m.def("read_mesh", [](const std::string& path) {
        TriangleMesh mesh;
        {
          stripweave_python::NativeCall release;
          mesh = read_mesh_file(path);
        }
        return py::make_tuple(rows<double, 3>(mesh.num_vertices(), [&](Index v) { return mesh.positions[v]; }),
                              rows<std::int32_t, 3>(mesh.num_triangles(), [&](Index t) { return mesh.triangles[t]; }));
      }, py::arg("path"), "Read a mesh file as stored: (vertices, triangles), nothing welded or repaired");

  m.def("write_mesh", [](const std::string& path, const Array3d& vertices, const Array3i& triangles) {
        TriangleMesh mesh = mesh_from_arrays(vertices, triangles);
        stripweave_python::NativeCall release;
        write_mesh_file(path, mesh);
      }, py::arg("path"), py::arg("vertices"), py::arg("triangles"));

  m.def("part_touching_faces", [](const Array3d& vertices, const Array3i& triangles, std::vector<Index> faces) {
        TriangleMesh mesh = mesh_from_arrays(vertices, triangles);
        if (faces.size() != mesh.triangles.size()) throw InputError("part_touching_faces: one face id per triangle");
        std::vector<EdgeKey> segments;
        std::vector<Index> corners;
        const Index split = part_touching_faces(mesh, faces, segments, corners);
        return py::make_tuple(rows<double, 3>(mesh.num_vertices(), [&](Index v) { return mesh.positions[v]; }),
                              rows<std::int32_t, 3>(mesh.num_triangles(), [&](Index t) { return mesh.triangles[t]; }),
                              faces, split);
      }, py::arg("vertices"), py::arg("triangles"), py::arg("faces"),
      "split_touching_edges.h on a welded tessellation with a B-rep face id per triangle: "
      "(vertices, triangles, faces, edges split)");

  m.def("zipper_fill", [](const std::vector<Index>& loop, const Array3d& vertices) {
        const std::vector<Vec3> positions = mesh_from_arrays(vertices, Array3i(std::vector<py::ssize_t>{0, 3})).positions;
        for (Index v : loop)
          if (v < 0 || v >= static_cast<Index>(positions.size())) throw InputError("zipper_fill: a loop vertex is out of range");
        return zipper_fill(loop, positions);
      }, py::arg("loop"), py::arg("vertices"), "zipper_fill.h: the triangles that close a boundary loop");

  m.def("_fp_trap_test", [](const std::string& kind) {
        stripweave_python::NativeCall release;
        raise_fp_trap_for_test(kind);
      }, py::arg("kind"), "Test entry (core/fp_guard.h): a floating-point trap inside a native call, which must "
      "end in an InputError (or nothing), never in a signal: gmp, gmp-worker, raise, float");

  stripweave_python::bind_loops(m);
  stripweave_python::bind_field(m);
  stripweave_python::bind_param(m);
  stripweave_python::bind_design(m);
  stripweave_python::bind_regions(m);
  stripweave_python::bind_surfacing(m);
  stripweave_python::bind_weave(m);
  stripweave_python::bind_render(m);
  stripweave_python::bind_symmetry(m);
}
