// Bindings of the cross field stage (paper §6.1).
//
// cross_field(session, loops, features=True, boundary=True, curvature=1.0) -> dict
//   Embeds each loop on the session's surface, cuts it into per-triangle
//   segments, and computes the cross field they constrain (cross_field.h;
//   curvature is the weight of the principal-direction prior).
//   Keys (T triangles, E edges; positions in MODEL units):
//     theta (T,)          the field's angle in each triangle's frame
//     direction (T,3)     unit direction of the field in each triangle
//     strength (T,)       |u| in [0,1]
//     constrained (T,)    uint8, 1 where a loop, feature or boundary fixed it
//     matching (E,)       int8 quarter turns across each edge
//     singularities       [{"vertex", "position" [x,y,z], "index"}], non-zero only
//     index_sum           sum of the singularities' indices
//     euler_characteristic  V - E + F of the surface mesh
//     solve_ms            the field computation's time
//   The computation releases the GIL.
//
// design_field(state) -> dict
//   The cross field a DesignState holds (its strips' loops, its options), with
//   the keys of cross_field(); nothing is recomputed.
//
// loop_segments(session, loop) -> dict
//   The loop's pieces per triangle (path_segments.h): "triangle" (K,),
//   "from", "to" (K,) indices into the embedded path's points, "direction"
//   (K,3) unit; "points" (N,3) the embedded path, model units.
#include "bind.h"

#include "stripweave/elastica/loop_session.h"
#include "stripweave/strips/cross_field.h"
#include "stripweave/strips/design_state.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

namespace {

template <typename T, typename F>
py::array_t<T> per_element(size_t count, F&& value) {
  py::array_t<T> out(static_cast<py::ssize_t>(count));
  auto a = out.template mutable_unchecked<1>();
  for (size_t i = 0; i < count; ++i) a(i) = static_cast<T>(value(i));
  return out;
}

py::dict field_dict(const Surface& s, const CrossField& f) {
  const size_t nt = f.theta.size();
  py::array_t<double> direction({static_cast<py::ssize_t>(nt), py::ssize_t(3)});
  auto d = direction.mutable_unchecked<2>();
  for (size_t t = 0; t < nt; ++t)
    for (int j = 0; j < 3; ++j) d(t, j) = f.direction[t][j];  // a similarity keeps directions

  py::list singularities;
  double index_sum = 0;
  for (const Singularity& sg : f.singularities) {
    const Vec3 p = s.similarity.to_model(s.mesh.positions[sg.vertex]);
    py::dict item;
    item["vertex"] = sg.vertex;
    item["position"] = std::vector<double>{p.x(), p.y(), p.z()};
    item["index"] = sg.index();
    singularities.append(item);
    index_sum += sg.index();
  }

  py::dict out;
  out["theta"] = per_element<double>(nt, [&](size_t t) { return f.theta[t]; });
  out["direction"] = direction;
  out["strength"] = per_element<double>(nt, [&](size_t t) { return f.strength[t]; });
  out["constrained"] = per_element<std::uint8_t>(nt, [&](size_t t) { return f.constrained[t]; });
  out["matching"] = per_element<std::int8_t>(f.matching.size(), [&](size_t e) { return f.matching[e]; });
  out["singularities"] = singularities;
  out["index_sum"] = index_sum;
  out["euler_characteristic"] = s.mesh.num_vertices() - s.topology.num_edges() + s.mesh.num_triangles();
  out["solve_ms"] = f.solve_ms;
  return out;
}

}  // namespace

void bind_field(py::module_& m) {
  m.def("loop_segments", [](const LoopSession& session, const Loop& loop) {
        const Surface& s = session.surface();
        SurfacePath path;
        std::vector<PathSegment> segments;
        {
          stripweave_python::NativeCall release;
          path = session.embed(loop);
          segments = path_segments(s, path, loop.closed);
        }
        const size_t k = segments.size();
        py::array_t<double> direction({static_cast<py::ssize_t>(k), py::ssize_t(3)});
        auto d = direction.mutable_unchecked<2>();
        for (size_t i = 0; i < k; ++i)
          for (int j = 0; j < 3; ++j) d(i, j) = segments[i].direction[j];
        py::array_t<double> points({static_cast<py::ssize_t>(path.points.size()), py::ssize_t(3)});
        auto p = points.mutable_unchecked<2>();
        for (size_t i = 0; i < path.points.size(); ++i) {
          const Vec3 q = s.similarity.to_model(path.points[i]);
          for (int j = 0; j < 3; ++j) p(i, j) = q[j];
        }
        py::dict out;
        out["triangle"] = per_element<std::int32_t>(k, [&](size_t i) { return segments[i].triangle; });
        out["from"] = per_element<std::int32_t>(k, [&](size_t i) { return segments[i].from; });
        out["to"] = per_element<std::int32_t>(k, [&](size_t i) { return segments[i].to; });
        out["direction"] = direction;
        out["points"] = points;
        return out;
      },
      py::arg("session"), py::arg("loop"), "The embedded loop cut into its pieces per triangle (paper §6.1)");

  m.def("cross_field", [](const LoopSession& session, const std::vector<Loop>& loops, bool features, bool boundary,
                          double curvature) {
        const Surface& s = session.surface();
        CrossField field;
        {
          stripweave_python::NativeCall release;
          std::vector<std::vector<PathSegment>> segments;
          segments.reserve(loops.size());
          for (const Loop& loop : loops) segments.push_back(path_segments(s, session.embed(loop), loop.closed));
          FieldOptions options;
          options.features = features;
          options.boundary = boundary;
          options.curvature = curvature;
          field = compute_cross_field(s, loop_constraints(segments), options);
        }
        return field_dict(s, field);
      },
      py::arg("session"), py::arg("loops"), py::arg("features") = true, py::arg("boundary") = true,
      py::arg("curvature") = FieldOptions().curvature,
      "The 4-RoSy cross field aligned with the loops (and with feature curves and open boundaries if asked), "
      "paper §6.1; positions in model units");

  m.def("design_field", [](const DesignState& d) { return field_dict(d.surface(), d.field()); }, py::arg("state"),
        "The cross field of a DesignState as cross_field() gives it (paper §6.1); model units");
}

}  // namespace stripweave_python
