// Bindings of the loop stage (paper §5): LoopSession and Loop.
//
// Points cross in MODEL units; the session works on the normalized surface.
// Queries release the GIL; a newer query cancels an older one (Cancelled).
#include "bind.h"

#include "stripweave/core/error.h"
#include "stripweave/elastica/loop_session.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <sstream>

namespace py = pybind11;
using namespace stripweave;

namespace stripweave_python {

namespace {

Vec3 vec3(const std::vector<double>& v, const char* what) {
  if (v.size() != 3) throw InputError(std::string(what) + " needs three coordinates");
  return {v[0], v[1], v[2]};
}

}  // namespace

// An anchor as (x, y, z) or (x, y, z, dx, dy, dz), model units.
// The point must lie within kAnchorReach bbox diagonals of the model's
// centre: a farther point cannot be on the part, and one near the double
// range (1e307) overflows the closest-point search, whose exact fallback
// (GMP) then kills the process with SIGFPE. Refused here, before any search.
Anchor anchor_from(const Surface& s, const std::vector<double>& a) {
  constexpr double kAnchorReach = 1e3;
  if (a.size() != 3 && a.size() != 6) throw InputError("an anchor is X,Y,Z or X,Y,Z,DX,DY,DZ");
  for (double x : a)
    if (!std::isfinite(x)) throw InputError("an anchor has a NaN or infinite coordinate");
  Anchor anchor;
  const Vec3 p(a[0], a[1], a[2]);
  anchor.point = s.similarity.to_normalized(p);
  const double reach = anchor.point.cwiseAbs().maxCoeff();
  if (!(reach <= kAnchorReach)) {
    std::ostringstream msg;
    msg << "an anchor at (" << p.x() << ", " << p.y() << ", " << p.z() << ") is " << reach
        << " bounding-box diagonals from the model's centre (at most " << kAnchorReach << "): it is off the part";
    throw InputError(msg.str());
  }
  if (a.size() == 6) {
    // Scaled before normalizing: the norm of (1e307, 1e307, 0) overflows.
    const Vec3 d(a[3], a[4], a[5]);
    const double big = d.cwiseAbs().maxCoeff();
    if (big == 0) throw InputError("an anchor direction must not be zero");
    anchor.direction = (d / big).normalized();
  }
  return anchor;
}

// Two anchors of one chain at one point (1e-9 of the diagonal apart) must not
// ask for different tangents: no curve passes one point in two directions
// (it gave a degenerate patch that was reported valid).
void check_anchor_chain(const std::vector<Anchor>& anchors) {
  constexpr double kSamePoint = 1e-9, kSameDirection = 0.9998;  // cos 1 degree
  for (size_t i = 0; i < anchors.size(); ++i)
    for (size_t j = i + 1; j < anchors.size(); ++j) {
      const Anchor &a = anchors[i], &b = anchors[j];
      if (!a.directional() || !b.directional() || (a.point - b.point).norm() > kSamePoint) continue;
      if (std::abs(a.direction.dot(b.direction)) >= kSameDirection) continue;
      throw InputError("anchors " + std::to_string(i + 1) + " and " + std::to_string(j + 1) +
                       " are at one point with different tangents: a curve passes a point in one direction");
    }
}

std::vector<Vec3> points_from(const py::handle& h, const std::string& what) {
  const auto a = py::cast<py::array_t<double, py::array::c_style | py::array::forcecast>>(h);
  if (a.ndim() != 2 || a.shape(1) != 3) throw InputError(what + " must be an (n, 3) array");
  const auto r = a.unchecked<2>();
  std::vector<Vec3> out(static_cast<size_t>(r.shape(0)));
  for (py::ssize_t i = 0; i < r.shape(0); ++i) out[i] = Vec3(r(i, 0), r(i, 1), r(i, 2));
  return out;
}

py::dict path_dict(const Surface& s, const SurfacePath& p) {
  py::array_t<double> points({static_cast<py::ssize_t>(p.points.size()), py::ssize_t(3)});
  auto pts = points.mutable_unchecked<2>();
  double length = 0;
  for (size_t i = 0; i < p.points.size(); ++i) {
    const Vec3 q = s.similarity.to_model(p.points[i]);
    for (int j = 0; j < 3; ++j) pts(i, j) = q[j];
    if (i > 0) length += (p.points[i] - p.points[i - 1]).norm() * s.similarity.scale;
  }
  py::dict d;
  d["points"] = points;
  d["vertex"] = p.vertex;
  d["edge"] = p.edge;
  d["t"] = p.t;
  d["node_start"] = p.node_start;
  d["length"] = length;
  return d;
}

void bind_loops(py::module_& m) {
  py::enum_<BoundaryMode>(m, "BoundaryMode")
      .value("aligned", BoundaryMode::Aligned)
      .value("trimmed", BoundaryMode::Trimmed);
  py::enum_<SearchAlgorithm>(m, "SearchAlgorithm")
      .value("dijkstra", SearchAlgorithm::Dijkstra)
      .value("astar", SearchAlgorithm::AStar)
      .value("bidirectional", SearchAlgorithm::Bidirectional);

  py::class_<ElasticaParams>(m, "ElasticaParams")
      .def(py::init<>())
      .def_readwrite("k", &ElasticaParams::k)
      .def_readwrite("max_turn_deg", &ElasticaParams::max_turn_deg)
      .def_readwrite("alpha", &ElasticaParams::alpha)
      .def_readwrite("beta", &ElasticaParams::beta)
      .def_readwrite("boundary", &ElasticaParams::boundary)
      .def_readwrite("feature_weight", &ElasticaParams::feature_weight);

  py::class_<Loop>(m, "Loop", "A dual loop (closed) or dual curve (open): a chain of g' nodes")
      .def_property_readonly("nodes", [](const Loop& l) { return l.nodes; })
      .def_readonly("closed", &Loop::closed)
      .def_readonly("cost", &Loop::cost)
      .def_readonly("length_term", &Loop::length_term)
      .def_readonly("alignment_term", &Loop::alignment_term)
      .def_readonly("curvature_term", &Loop::curvature_term)
      .def_property_readonly("max_turn_deg", [](const Loop& l) { return l.max_turn * 180.0 / M_PI; });

  py::class_<LoopSession, std::shared_ptr<LoopSession>>(m, "LoopSession",
                                                        "The elastica graph of a surface and its loop queries")
      .def(py::init([](std::shared_ptr<Surface> surface, const ElasticaParams& params, Progress* progress) {
             stripweave_python::NativeCall release;
             return std::make_shared<LoopSession>(surface, params, progress);
           }),
           py::arg("surface"), py::arg("params") = ElasticaParams(), py::arg("progress") = nullptr)
      .def_property_readonly("build_ms", &LoopSession::build_ms)
      .def_property("algorithm", [](const LoopSession& s) { return s.algorithm; },
                    [](LoopSession& s, SearchAlgorithm a) { s.algorithm = a; })
      .def_property("max_anchor_distance",
                    [](const LoopSession& s) { return s.max_anchor_distance * s.surface().similarity.scale; },
                    [](LoopSession& s, double d) { s.max_anchor_distance = d / s.surface().similarity.scale; },
                    "anchors farther than this from the surface are an error (model units)")
      .def("graph_stats", [](const LoopSession& s) {
        const ElasticaGraph& g = s.graph();
        py::dict d;
        d["g_nodes"] = s.surface().mesh.num_vertices();
        d["gprime_nodes"] = g.num_nodes();
        d["gprime_edges"] = g.num_arcs();
        d["graph_mb"] = g.memory_bytes() / (1024.0 * 1024.0);
        d["graph_build_s"] = s.build_ms() / 1000.0;
        return d;
      })
      .def("loops", [](LoopSession& s, const std::vector<std::vector<double>>& anchors, int count, bool allow_open) {
             std::vector<Anchor> parsed;
             for (const auto& a : anchors) parsed.push_back(anchor_from(s.surface(), a));
             check_anchor_chain(parsed);
             stripweave_python::NativeCall release;
             return s.loops(parsed, count, allow_open);
           },
           py::arg("anchors"), py::arg("count") = 1, py::arg("allow_open") = true,
           "Up to `count` distinct loops through the anchors (model units), cheapest first")
      .def("best_loop", [](LoopSession& s, const std::vector<double>& point, bool allow_open) {
             const Anchor a = anchor_from(s.surface(), point);
             stripweave_python::NativeCall release;
             return s.best_loop(a.point, allow_open);
           },
           py::arg("point"), py::arg("allow_open") = true, "Hover: the best loop through a point, all directions")
      .def("embed", [](const LoopSession& s, const Loop& loop) {
             SurfacePath p;
             {
               stripweave_python::NativeCall release;
               p = s.embed(loop);
             }
             return path_dict(s.surface(), p);
           },
           "The loop on the surface: points (model units), per point its mesh vertex or mesh edge and parameter")
      .def("anchor_candidates", [](LoopSession& s, const std::vector<double>& a) {
        const ResolvedAnchor r = s.resolve(anchor_from(s.surface(), a));
        return py::make_tuple(r.vertex, r.candidates);
      })
      .def("node_tangent", [](const LoopSession& s, Index node) {
        const Vec3 t = s.graph().tangent(s.surface(), node);
        return std::vector<double>{t.x(), t.y(), t.z()};
      })
      .def("reverse_node", [](const LoopSession& s, Index node) { return s.graph().reverse.at(node); },
           "the g' node of the same g edge run the other way")
      .def("node_vertices", [](const LoopSession& s, Index node) {
        return py::make_tuple(s.graph().tail.at(node), s.graph().head.at(node));
      })
      // g' as it is stored (CSR), for tests that search it independently:
      // node i's arcs are offsets[i]..offsets[i+1] into head and weight (w(e')
      // of eq. (2), the loop cost being their sum along the node chain).
      .def("graph_arcs", [](const LoopSession& s) {
        const ElasticaGraph& g = s.graph();
        py::array_t<std::int64_t> offsets(static_cast<py::ssize_t>(g.arc_offsets.size()));
        py::array_t<std::int64_t> head(static_cast<py::ssize_t>(g.num_arcs()));
        py::array_t<double> weight(static_cast<py::ssize_t>(g.num_arcs()));
        auto o = offsets.mutable_unchecked<1>();
        auto h = head.mutable_unchecked<1>();
        auto w = weight.mutable_unchecked<1>();
        for (size_t i = 0; i < g.arc_offsets.size(); ++i) o(i) = g.arc_offsets[i];
        for (Index a = 0; a < g.num_arcs(); ++a) h(a) = g.arc_head[a], w(a) = g.arc_weight[a];
        py::dict d;
        d["offsets"] = offsets;
        d["head"] = head;
        d["weight"] = weight;
        return d;
      })
      .def("set_threads", &LoopSession::set_threads, py::arg("threads"),
           "threads a query may use (default: two, one per core)")
      .def_property_readonly("threads", &LoopSession::threads, "threads a query may use")
      .def_property_readonly("workspace_bytes", &LoopSession::workspace_bytes,
                             "bytes of search scratch space held (allocated by the first query)")
      .def("release_workspaces", &LoopSession::release_workspaces,
           "free the search scratch space (the next query allocates it again; results do not change)")
      .def("release_graph", &LoopSession::release_graph,
           "free g' and the search state (a job done with queries); later uses of the graph raise InputError")
      .def_property_readonly("graph_released", &LoopSession::graph_released)
      .def("set_disabled", &LoopSession::set_disabled, py::arg("nodes"), py::arg("disabled") = true)
      .def("clear_disabled", &LoopSession::clear_disabled)
      .def("cancel", &LoopSession::cancel)
      .def_readwrite("max_query_polls", &LoopSession::max_query_polls,
                     "deterministic cap on a query's work (polls, one per 4096 settled g' nodes; 0: none): "
                     "past it the query raises Cancelled and query_limited is set")
      .def_property_readonly("query_limited", &LoopSession::query_limited,
                             "the last query stopped at max_query_polls")
      .def_property_readonly("last_query_polls", &LoopSession::last_query_polls,
                             "the polls the last query made (its work)");
}

}  // namespace stripweave_python
