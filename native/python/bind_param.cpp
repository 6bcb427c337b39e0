// Bindings of the global parameterization S (paper §6.1).
//
// parameterize(session, loops, features=True, boundary=True) -> dict
//   Embeds each loop (session.embed), splits it into per-triangle segments,
//   computes the cross field constrained by the loops (and by feature curves
//   and open boundaries if asked) and then S. Runs without the GIL.
//   Lengths are in MODEL units (uv, translations, loop values, residuals).
//   Keys:
//     uv            (T, 3, 2) corner coordinates per triangle, in its chart
//     flipped       (T,) 1 where the chart is clockwise (a fold-over)
//     fold_overs    their count
//     comb          (T,) quarter turns combing the field
//     direction     (T, 3) the field's direction (before combing)
//     on_cut        (E,) 1 for a cut edge
//     edge_triangles (E, 2) the triangles of each edge (-1 on the boundary)
//     transition_r  (E,) and transition_tr (E, 2): chart of edge_triangles[e][1]
//                   = R^r (chart of [0]) + tr, R the counter-clockwise quarter turn
//     cut_ends      vertices the cut had to reach
//     singularities list of {"vertex", "position", "index"} as in cross_field()
//     loops         per loop, per segment: "axis" (0: u, 1: v constant),
//                   "value" (that coordinate), "triangles", "from", "to"
//                   (indices into path["points"]), "points_uv" (n, 2, 2):
//                   each segment's two end points in its triangle's chart,
//                   "residual" (n,): |c(from) - c(to)| of the across
//                   coordinate c; and "max_residual", "closed", "path"
//                   (the embedded loop, as LoopSession.embed returns it)
//     constraint_residual, solve_ms, field_ms, segments_ms, timings_ms
#include "bind.h"

#include "stripweave/core/error.h"
#include "stripweave/strips/design_state.h"
#include "stripweave/strips/parameterization.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <chrono>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

namespace {

using Clock = std::chrono::steady_clock;
double millis(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

struct Solved {
  std::vector<LoopPath> loops;
  CrossField field;
  Parameterization param;
  double segments_ms = 0, field_ms = 0;
};

Solved solve(const LoopSession& session, const std::vector<Loop>& loops, bool features, bool boundary) {
  const Surface& s = session.surface();
  Solved out;
  const auto t0 = Clock::now();
  std::vector<std::vector<PathSegment>> segments;
  for (const Loop& loop : loops) {
    out.loops.push_back(loop_path(session, loop));
    segments.push_back(out.loops.back().segments);
  }
  const auto t1 = Clock::now();
  FieldOptions options;
  options.features = features;
  options.boundary = boundary;
  out.field = compute_cross_field(s, loop_constraints(segments), options);
  const auto t2 = Clock::now();
  out.param = parameterize(s, out.field, out.loops);
  out.segments_ms = millis(t0, t1);
  out.field_ms = millis(t1, t2);
  return out;
}

py::dict to_dict(const Surface& s, const Solved& solved) {
  const double scale = s.similarity.scale;
  const Parameterization& p = solved.param;
  const MeshTopology& topo = s.topology;
  const py::ssize_t T = s.mesh.num_triangles(), E = topo.num_edges();

  py::array_t<double> uv({T, py::ssize_t(3), py::ssize_t(2)});
  auto a = uv.mutable_unchecked<3>();
  for (py::ssize_t t = 0; t < T; ++t)
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 2; ++k) a(t, i, k) = p.uv[t][i][k] * scale;

  py::array_t<double> direction({T, py::ssize_t(3)});
  auto d = direction.mutable_unchecked<2>();
  for (py::ssize_t t = 0; t < T; ++t)
    for (int k = 0; k < 3; ++k) d(t, k) = solved.field.direction[t][k];

  py::array_t<std::int32_t> edge_triangles({E, py::ssize_t(2)});
  py::array_t<std::int32_t> transition_r(E);
  py::array_t<double> transition_tr({E, py::ssize_t(2)});
  auto et = edge_triangles.mutable_unchecked<2>();
  auto tr = transition_r.mutable_unchecked<1>();
  auto tt = transition_tr.mutable_unchecked<2>();
  for (py::ssize_t e = 0; e < E; ++e) {
    et(e, 0) = topo.edge_triangles[e][0], et(e, 1) = topo.edge_triangles[e][1];
    tr(e) = p.transition[e].r;
    tt(e, 0) = p.transition[e].tr.x() * scale, tt(e, 1) = p.transition[e].tr.y() * scale;
  }

  py::list singularities;
  for (const Singularity& x : solved.field.singularities) {
    py::dict sd;
    sd["vertex"] = x.vertex;
    sd["index"] = x.index();
    const Vec3 q = s.similarity.to_model(s.mesh.positions[x.vertex]);
    sd["position"] = std::vector<double>{q.x(), q.y(), q.z()};
    singularities.append(sd);
  }

  py::list loops;
  for (size_t l = 0; l < solved.loops.size(); ++l) {
    const LoopPath& lp = solved.loops[l];
    const py::ssize_t n = static_cast<py::ssize_t>(lp.segments.size());
    py::array_t<double> points({n, py::ssize_t(2), py::ssize_t(2)});
    py::array_t<double> residual(n);
    auto pts = points.mutable_unchecked<3>();
    auto res = residual.mutable_unchecked<1>();
    std::vector<double> value;
    std::vector<Index> triangles, from, to;
    double max_residual = 0;
    for (py::ssize_t k = 0; k < n; ++k) {
      const auto& ends = p.loop_points_uv[l][k];
      for (int j = 0; j < 2; ++j)
        for (int c = 0; c < 2; ++c) pts(k, j, c) = ends[j][c] * scale;
      const int axis = p.loop_axis[l][k];
      res(k) = std::abs(ends[0][axis] - ends[1][axis]) * scale;
      max_residual = std::max(max_residual, res(k));
      value.push_back(p.loop_value[l][k] * scale);
      triangles.push_back(lp.segments[k].triangle);
      from.push_back(lp.segments[k].from);
      to.push_back(lp.segments[k].to);
    }
    py::dict ld;
    ld["axis"] = p.loop_axis[l];
    ld["value"] = value;
    ld["triangles"] = triangles;
    ld["from"] = from;
    ld["to"] = to;
    ld["points_uv"] = points;
    ld["residual"] = residual;
    ld["max_residual"] = max_residual;
    ld["closed"] = lp.closed;
    ld["path"] = path_dict(s, lp.path);
    loops.append(ld);
  }

  py::dict timings;
  for (const auto& [name, ms] : p.timings) timings[py::str(name)] = ms;

  py::dict out;
  out["uv"] = uv;
  out["flipped"] = std::vector<int>(p.flipped.begin(), p.flipped.end());
  out["fold_overs"] = p.fold_overs;
  out["comb"] = std::vector<int>(p.comb.begin(), p.comb.end());
  out["direction"] = direction;
  out["on_cut"] = std::vector<int>(p.on_cut.begin(), p.on_cut.end());
  out["edge_triangles"] = edge_triangles;
  out["transition_r"] = transition_r;
  out["transition_tr"] = transition_tr;
  out["cut_ends"] = p.cut_ends;
  out["singularities"] = singularities;
  out["loops"] = loops;
  out["constraint_residual"] = p.constraint_residual * scale;
  out["solve_ms"] = p.solve_ms;
  out["field_ms"] = solved.field_ms;
  out["segments_ms"] = solved.segments_ms;
  out["timings_ms"] = timings;
  return out;
}

}  // namespace

void bind_param(py::module_& m) {
  m.def("parameterize", [](const LoopSession& session, const std::vector<Loop>& loops, bool features, bool boundary) {
        Solved solved;
        {
          stripweave_python::NativeCall release;
          solved = solve(session, loops, features, boundary);
        }
        return to_dict(session.surface(), solved);
      },
      py::arg("session"), py::arg("loops"), py::arg("features") = true, py::arg("boundary") = true,
      "The global parameterization S in which every loop is an isocurve (paper §6.1), with its cross field; "
      "model units");
}

}  // namespace stripweave_python
