// The global parameterization S (paper §6.1; see the header).
//
// The unknowns are the coordinates (u, v) of every wedge (a vertex copy on one
// side of the cut, cut_graph.h), u and v in two blocks. S minimizes the
// alignment-and-isometry energy
//   E(u, v) = 1/2 sum_t A_t (|grad u - f_t|^2 + |grad v - f_t^perp|^2),
// f_t the combed field (unit) and f_t^perp = n_t x f_t, subject to the linear
// constraints C x = 0:
//   transition  for a cut edge e = (a, b) between t0 and t1, the two copies of
//               each end satisfy x1 = R^r x0 + tr with one tr for both ends:
//               (a1 - R^r a0) - (b1 - R^r b0) = 0 (two rows);
//   isocurve    for a loop segment from P to Q in triangle t, the coordinate
//               across the loop takes one value: c(P) - c(Q) = 0, c the
//               barycentric interpolation of t's corner coordinates;
//   gauge       one wedge per connected component is pinned at (0, 0) (it is
//               left out of the unknowns).
// E is translation invariant and every constraint homogeneous, so the gauge
// only fixes the position of S. The first-order conditions form the KKT
// system
//   [ H  C^T ] [x]   [b]
//   [ C  -dI ] [l] = [0],      d = 1e-12,
// H = blockdiag(L, L) with L the cotangent Laplacian of the cut surface. The
// tiny d makes the matrix quasi-definite, so it has an LDL^T factorization
// in any symmetric order, and it lets redundant constraints (the closing
// isocurve constraint of a loop that never crosses the cut, say) through
// without harm. It is factored once (sparse/supernodal_ldlt.h) in a
// fill-reducing order of the unknowns in which every constraint row comes
// right after the last of its unknowns: a constraint is never a pivot before
// its unknowns (which would turn d into a 1/d-sized update), and a redundant
// one meets a pivot near -d with a row that is zero up to rounding. A step
// of iterative refinement against the system without d removes what d and
// rounding leave in the constraints.
#include "stripweave/strips/parameterization.h"

#include "stripweave/core/error.h"
#include "stripweave/sparse/nested_dissection.h"
#include "stripweave/sparse/supernodal_ldlt.h"
#include "stripweave/strips/cut_graph.h"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace stripweave {

namespace {

using Clock = std::chrono::steady_clock;
using Triplet = Eigen::Triplet<double, int>;

constexpr double kRegularization = 1e-12;
// Constraint residuals above this (normalized units: the model's diagonal
// is 1) mean the solve failed; the contract promises 1e-9.
constexpr double kResidualTolerance = 1e-9;
// The membrane weight across the edges of a zero-area triangle (see the
// energy below): a millionth of an equilateral triangle's cotangent weight.
constexpr double kDegenerateMembrane = 1e-6;

int mod4(int r) { return ((r % 4) + 4) % 4; }

// R^r p, R the counter-clockwise quarter turn: component k of R^r p is
// sign(r, k) * p[source(r, k)].
int source(int r, int k) { return (r & 1) ? 1 - k : k; }
double sign(int r, int k) {
  static const double s[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  return s[r][k];
}
Vec2 turn(const Vec2& p, int r) {
  r = mod4(r);
  return {sign(r, 0) * p[source(r, 0)], sign(r, 1) * p[source(r, 1)]};
}

double millis(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// One linear constraint sum coef[i] * x[var[i]] = 0 over at most four
// unknowns (pinned unknowns, var < 0, are zero and left out).
struct Row {
  int n = 0;
  std::array<Index, 4> var{};
  std::array<double, 4> coef{};
  void add(Index v, double c) {
    if (v < 0 || c == 0) return;
    for (int i = 0; i < n; ++i)
      if (var[i] == v) {
        coef[i] += c;
        return;
      }
    var[n] = v, coef[n] = c, ++n;
  }
  // Drop coefficients that cancelled (a wedge on both sides of an edge at
  // the end of a cut branch), and scale the row so that its largest
  // coefficient is 1: an isocurve constraint of a short segment has
  // coefficients as small as the segment, and such a row would look almost
  // redundant to the solver (a singular value of 1e-6 against the 1e-12
  // regularization stalls the refinement).
  void tidy() {
    double norm = 0;
    for (int i = 0; i < n; ++i) norm = std::max(norm, std::abs(coef[i]));
    int k = 0;
    for (int i = 0; i < n; ++i)
      if (std::abs(coef[i]) > 1e-12 * norm) var[k] = var[i], coef[k] = coef[i] / norm, ++k;
    n = k;
  }
};

Index corner_of(const Tri& f, Index v) { return f[0] == v ? 0 : f[1] == v ? 1 : 2; }

std::string model_point(const Surface& s, const Vec3& p) {
  const Vec3 q = s.similarity.to_model(p);
  std::ostringstream out;
  out.precision(4);
  out << "(" << q.x() << ", " << q.y() << ", " << q.z() << ")";
  return out.str();
}

// --- Contradicting isocurve constraints ---------------------------------------
//
// Loops must cross transversally (§6.2). Where two loops (or two passes of
// one loop) meet while the same coordinate is to be constant along both, S
// would have to be constant along two directions there: the strips collapse.
// All constraints are homogeneous, so no residual reveals this; it is found
// combinatorially, before the solve.

struct SegmentRef {
  Index loop, k;
};

bool same_pass(const std::vector<LoopPath>& loops, const SegmentRef& a, const SegmentRef& b) {
  if (a.loop != b.loop) return false;
  const Index n = static_cast<Index>(loops[a.loop].segments.size());
  const Index d = std::abs(a.k - b.k);
  return d <= 1 || (loops[a.loop].closed && d == n - 1);
}

// Do segments pq and rs of one triangle (barycentric points as affine 2D
// coordinates) intersect or touch?
bool segments_meet(const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s) {
  constexpr double eps = 1e-9;
  auto cross = [](const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); };
  const double d1 = cross(q - p, r - p), d2 = cross(q - p, s - p);
  const double d3 = cross(s - r, p - r), d4 = cross(s - r, q - r);
  if (((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps)) && ((d3 > eps && d4 < -eps) || (d3 < -eps && d4 > eps)))
    return true;
  // Touching: an end point on the other segment.
  auto on = [&](const Vec2& a, const Vec2& b, const Vec2& x) {
    if (std::abs(cross(b - a, x - a)) > eps * std::max(1.0, (b - a).norm())) return false;
    const double t = (x - a).dot(b - a), l2 = (b - a).squaredNorm();
    return t >= -eps && t <= l2 + eps;
  };
  return on(p, q, r) || on(p, q, s) || on(r, s, p) || on(r, s, q);
}

[[noreturn]] void throw_meeting(const Surface& s, const LoopMeeting& meeting) {
  std::ostringstream m;
  if (meeting.loop_a == meeting.loop_b)
    m << "loop " << meeting.loop_a << " meets itself";
  else
    m << "loops " << meeting.loop_a << " and " << meeting.loop_b << " meet";
  m << " near " << model_point(s, meeting.where)
    << " running in the same direction of the cross field: both would have to be isocurves of the same coordinate "
       "there, so the strips would collapse; loops must cross transversally";
  throw InputError(m.str());
}

// Every contradicting meeting, in the order of the two tests below.
std::vector<LoopMeeting> meetings_of(const Surface& s, const CutGraph& cut, const std::vector<LoopPath>& loops,
                                     const std::vector<std::vector<int>>& axis) {
  std::vector<LoopMeeting> found;
  const TriangleMesh& mesh = s.mesh;
  const MeshTopology& topo = s.topology;

  // (1) Segments in one triangle (this includes loops meeting on an edge).
  std::vector<std::pair<Index, SegmentRef>> by_triangle;
  for (Index l = 0; l < static_cast<Index>(loops.size()); ++l)
    for (Index k = 0; k < static_cast<Index>(loops[l].segments.size()); ++k)
      by_triangle.push_back({loops[l].segments[k].triangle, {l, k}});
  std::sort(by_triangle.begin(), by_triangle.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second.loop != b.second.loop ? a.second.loop < b.second.loop
                                                                                    : a.second.k < b.second.k;
  });
  auto ends = [&](const SegmentRef& r, Index t) {
    const LoopPath& lp = loops[r.loop];
    const PathSegment& g = lp.segments[r.k];
    const Vec3 bp = barycentric_in(s, lp.path, g.from, t), bq = barycentric_in(s, lp.path, g.to, t);
    return std::pair<Vec2, Vec2>{Vec2(bp[1], bp[2]), Vec2(bq[1], bq[2])};
  };
  for (size_t i = 0; i < by_triangle.size();) {
    size_t j = i;
    while (j < by_triangle.size() && by_triangle[j].first == by_triangle[i].first) ++j;
    const Index t = by_triangle[i].first;
    for (size_t a = i; a < j; ++a)
      for (size_t b = a + 1; b < j; ++b) {
        const SegmentRef& ra = by_triangle[a].second;
        const SegmentRef& rb = by_triangle[b].second;
        if (same_pass(loops, ra, rb) || axis[ra.loop][ra.k] != axis[rb.loop][rb.k]) continue;
        const auto [p, q] = ends(ra, t);
        const auto [r, w] = ends(rb, t);
        if (segments_meet(p, q, r, w)) {
          const Tri& f = mesh.triangles[t];
          found.push_back({ra.loop, ra.k, rb.loop, rb.k,
                           (mesh.positions[f[0]] + mesh.positions[f[1]] + mesh.positions[f[2]]) / 3});
        }
      }
    i = j;
  }

  // (2) Segments around a common vertex, compared in one chart: the charts
  // of the triangles around the vertex differ by the cut's rotations, and an
  // odd quarter turn swaps u and v.
  struct AtVertex {
    Index vertex;
    SegmentRef ref;
    Index triangle;
  };
  std::vector<AtVertex> at;
  for (Index l = 0; l < static_cast<Index>(loops.size()); ++l) {
    const LoopPath& lp = loops[l];
    for (Index k = 0; k < static_cast<Index>(lp.segments.size()); ++k)
      for (Index i : {lp.segments[k].from, lp.segments[k].to})
        if (lp.path.vertex[i] != kInvalid) at.push_back({lp.path.vertex[i], {l, k}, lp.segments[k].triangle});
  }
  std::sort(at.begin(), at.end(), [](const AtVertex& a, const AtVertex& b) { return a.vertex < b.vertex; });
  std::vector<Index> fan, rot;
  for (size_t i = 0; i < at.size();) {
    size_t j = i;
    bool several = false;
    while (j < at.size() && at[j].vertex == at[i].vertex) {
      several |= !same_pass(loops, at[i].ref, at[j].ref);
      ++j;
    }
    if (several) {
      // Chart rotations of the fan relative to its first triangle, by a walk
      // through the edges at the vertex.
      const Index v = at[i].vertex;
      fan.assign(topo.vertex_triangles.begin(v), topo.vertex_triangles.end(v));
      rot.assign(fan.size(), -1);
      rot[0] = 0;
      for (bool grew = true; grew;) {
        grew = false;
        for (size_t a = 0; a < fan.size(); ++a) {
          if (rot[a] < 0) continue;
          for (Index e : topo.triangle_edges[fan[a]]) {
            const auto [t0, t1] = topo.edge_triangles[e];
            if (t1 == kInvalid || (topo.edges[e][0] != v && topo.edges[e][1] != v)) continue;
            const Index other = t0 == fan[a] ? t1 : t0;
            const size_t b = std::find(fan.begin(), fan.end(), other) - fan.begin();
            if (b == fan.size() || rot[b] >= 0) continue;
            const int r = mod4(4 - cut.combed_matching[e]);  // chart_t1 = R^r chart_t0 + tr
            rot[b] = mod4(rot[a] + (t0 == fan[a] ? r : -r));
            grew = true;
          }
        }
      }
      auto axis_in_fan = [&](const AtVertex& x) {
        const size_t a = std::find(fan.begin(), fan.end(), x.triangle) - fan.begin();
        const int r = a < fan.size() && rot[a] >= 0 ? rot[a] : 0;
        return axis[x.ref.loop][x.ref.k] ^ (r & 1);
      };
      for (size_t a = i; a < j; ++a)
        for (size_t b = a + 1; b < j; ++b)
          if (!same_pass(loops, at[a].ref, at[b].ref) && axis_in_fan(at[a]) == axis_in_fan(at[b]))
            found.push_back({at[a].ref.loop, at[a].ref.k, at[b].ref.loop, at[b].ref.k, mesh.positions[v]});
    }
    i = j;
  }
  return found;
}

// The coordinate across each loop segment: where the loop runs along the
// combed field (f, per triangle) it is an isocurve of v, where it runs along
// f^perp of u (n: the triangles' unit normals).
std::vector<std::vector<int>> loop_axes(const std::vector<Vec3>& f, const std::vector<Vec3>& n,
                                        const std::vector<LoopPath>& loops) {
  std::vector<std::vector<int>> axis(loops.size());
  for (size_t l = 0; l < loops.size(); ++l)
    for (const PathSegment& g : loops[l].segments) {
      const Index t = g.triangle;
      const double along_u = std::abs(g.direction.dot(f[t])), along_v = std::abs(g.direction.dot(n[t].cross(f[t])));
      axis[l].push_back(along_u >= along_v ? 1 : 0);
    }
  return axis;
}

// Per triangle its unit normal (n) and combed field direction (f).
void combed_frames(const Surface& surface, const CrossField& field, const CutGraph& cut, std::vector<Vec3>& f,
                   std::vector<Vec3>& n) {
  const Index F = surface.mesh.num_triangles();
  f.resize(F), n.resize(F);
  for (Index t = 0; t < F; ++t) {
    n[t] = unit_normal(surface.mesh, t);
    f[t] = combed_direction(surface, field, cut, t);
  }
}


// The unknowns: per wedge its index among the free wedges (-1: pinned, one
// per connected component), u of all free wedges, then v.
struct Unknowns {
  std::vector<Index> slot;
  Index free_wedges = 0;
  Index n_primal = 0;
  Index var(Index w, int axis) const { return slot[w] < 0 ? -1 : slot[w] + axis * free_wedges; }
};

Unknowns unknowns_of(const CutGraph& cut) {
  Unknowns x;
  x.slot.assign(cut.num_wedges(), 0);
  for (Index c = 0; c < cut.num_components(); ++c) x.slot[cut.wedge_of(cut.tree_root[c], 0)] = -1;
  for (Index& s : x.slot)
    if (s == 0) s = x.free_wedges++;
  x.n_primal = 2 * x.free_wedges;
  return x;
}

// The constraint rows: two transition rows per cut edge, one isocurve row
// per loop segment (rows that vanish, all their unknowns pinned, left out).
std::vector<Row> constraint_rows(const Surface& surface, const CutGraph& cut, const std::vector<LoopPath>& loops,
                                 const std::vector<std::vector<int>>& loop_axis, const Unknowns& x) {
  const TriangleMesh& mesh = surface.mesh;
  const MeshTopology& topo = surface.topology;
  std::vector<Row> rows;
  for (Index e = 0; e < topo.num_edges(); ++e) {
    if (!cut.on_cut[e]) continue;
    const auto [t0, t1] = topo.edge_triangles[e];
    const int r = mod4(4 - cut.combed_matching[e]);
    const Index a = topo.edges[e][0], b = topo.edges[e][1];
    const Index a0 = cut.wedge_of(t0, corner_of(mesh.triangles[t0], a));
    const Index a1 = cut.wedge_of(t1, corner_of(mesh.triangles[t1], a));
    const Index b0 = cut.wedge_of(t0, corner_of(mesh.triangles[t0], b));
    const Index b1 = cut.wedge_of(t1, corner_of(mesh.triangles[t1], b));
    for (int k = 0; k < 2; ++k) {
      Row row;
      row.add(x.var(a1, k), 1);
      row.add(x.var(a0, source(r, k)), -sign(r, k));
      row.add(x.var(b1, k), -1);
      row.add(x.var(b0, source(r, k)), sign(r, k));
      row.tidy();
      if (row.n > 0) rows.push_back(row);
    }
  }
  for (size_t l = 0; l < loops.size(); ++l) {
    const LoopPath& lp = loops[l];
    for (size_t k = 0; k < lp.segments.size(); ++k) {
      const PathSegment& g = lp.segments[k];
      const Vec3 bp = barycentric_in(surface, lp.path, g.from, g.triangle);
      const Vec3 bq = barycentric_in(surface, lp.path, g.to, g.triangle);
      Row row;
      for (int c = 0; c < 3; ++c) row.add(x.var(cut.wedge_of(g.triangle, c), loop_axis[l][k]), bp[c] - bq[c]);
      row.tidy();
      if (row.n > 0) rows.push_back(row);
    }
  }
  return rows;
}

// The energy's Hessian H (lower triangle, triplets) and gradient term
// (rhs, sized for the unknowns and the n_rows constraints). In triangle t
// the hat function of corner i has the constant gradient
// n x (p[i+2] - p[i+1]) / 2A, so A grad(phi_i).grad(phi_j) is the usual
// cotangent weight and A f.grad(phi_i) = f.(n x e_i) / 2.
void energy(const Surface& surface, const CutGraph& cut, const std::vector<Vec3>& f, const std::vector<Vec3>& n,
            const Unknowns& x, Index n_rows, std::vector<Triplet>& h, Eigen::VectorXd& rhs) {
  const TriangleMesh& mesh = surface.mesh;
  const Index F = mesh.num_triangles();
  h.reserve(9 * 2 * static_cast<size_t>(F));
  rhs = Eigen::VectorXd::Zero(x.n_primal + n_rows);
  for (Index t = 0; t < F; ++t) {
    const Tri& tri = mesh.triangles[t];
    const double a2 = triangle_normal_area2(mesh, t).norm();
    if (!(a2 > 1e-24)) {
      // A zero-area triangle (coincident or collinear corners, as B-rep
      // tessellations leave at poles and closed gaps) has no gradient to
      // fit, yet its corners are unknowns. Where the cut isolates a wedge
      // whose triangles are all such, nothing else fixes its value and the
      // factorization meets a zero pivot. A faint membrane across the
      // triangle's edges gives such a wedge the mean of its neighbours (for
      // coincident corners, the value of its twin: the limit of a shrinking
      // triangle) and moves nothing where triangles have area.
      for (int i = 0; i < 3; ++i)
        for (int axis = 0; axis < 2; ++axis) {
          const Index p = x.var(cut.wedge_of(t, i), axis), q = x.var(cut.wedge_of(t, (i + 1) % 3), axis);
          if (p >= 0) h.emplace_back(p, p, kDegenerateMembrane);
          if (q >= 0) h.emplace_back(q, q, kDegenerateMembrane);
          if (p >= 0 && q >= 0 && p != q) h.emplace_back(std::max(p, q), std::min(p, q), -kDegenerateMembrane);
        }
      continue;
    }
    std::array<Vec3, 3> g;  // 2A grad(phi_i)
    for (int i = 0; i < 3; ++i)
      g[i] = n[t].cross(mesh.positions[tri[(i + 2) % 3]] - mesh.positions[tri[(i + 1) % 3]]);
    const Vec3 fu = f[t], fv = n[t].cross(f[t]);
    for (int i = 0; i < 3; ++i) {
      const Index w = cut.wedge_of(t, i);
      for (int axis = 0; axis < 2; ++axis) {
        const Index p = x.var(w, axis);
        if (p < 0) continue;
        rhs[p] += 0.5 * (axis == 0 ? fu : fv).dot(g[i]);
        for (int j = 0; j < 3; ++j) {
          const Index q = x.var(cut.wedge_of(t, j), axis);
          if (q >= 0 && q <= p) h.emplace_back(p, q, g[i].dot(g[j]) / (2 * a2));
        }
      }
    }
  }
}

// The elimination order, as each unknown's and constraint's position: the
// surface's nested dissection, wedge by wedge (the copies of a vertex side
// by side), each wedge's u right before its v, then each constraint right
// after its last unknown. Cutting only splits vertices, and a transition
// only ties copies of an edge's two ends, so the vertices' separators still
// separate the unknowns: the order depends on the mesh alone and is computed
// once per surface. (Dissecting the graph of all 2W unknowns per design,
// which sees that u and v are two sheets tied only where a transition turns
// by an odd quarter, factors some 30% faster but costs twice that in
// ordering; minimum degree, per design, costs as much to order and factors
// 1.5 times slower.)
std::vector<Index> elimination_positions(const Surface& surface, const CutGraph& cut, const Unknowns& x,
                                         const std::vector<Row>& rows, const std::vector<Index>& vertex_order) {
  const Index n_primal = x.n_primal, n_rows = static_cast<Index>(rows.size());
  const Index nv = surface.mesh.num_vertices();
  const std::vector<Index> by_rank = vertex_order.empty() ? vertex_elimination_order(surface) : vertex_order;
  if (static_cast<Index>(by_rank.size()) != nv)
    throw std::invalid_argument("parameterize: the vertex order does not belong to this surface");
  std::vector<std::vector<Index>> wedges_of(nv);
  for (Index w = 0; w < cut.num_wedges(); ++w) wedges_of[cut.wedge_vertex[w]].push_back(w);
  std::vector<Index> order;
  order.reserve(n_primal);
  for (Index v : by_rank)
    for (Index w : wedges_of[v])
      if (x.slot[w] >= 0) order.push_back(x.var(w, 0)), order.push_back(x.var(w, 1));
  std::vector<Index> rank(n_primal);
  for (Index k = 0; k < n_primal; ++k) rank[order[k]] = k;
  std::vector<std::vector<Index>> after(n_primal);
  for (Index c = 0; c < n_rows; ++c) {
    Index last = 0;
    for (int i = 0; i < rows[c].n; ++i) last = std::max(last, rank[rows[c].var[i]]);
    after[last].push_back(c);
  }
  std::vector<Index> position(n_primal + n_rows);
  Index next = 0;
  for (Index k = 0; k < n_primal; ++k) {
    position[order[k]] = next++;
    for (Index c : after[k]) position[n_primal + c] = next++;
  }
  return position;
}

// The KKT matrix, lower triangle, in elimination order; H's triplets are
// released as they are used (they and the KKT triplets go before the
// factorization, the peak of the solve: some 17 MB at 30K triangles).
SparseMatrix kkt_matrix(std::vector<Triplet>& h, const std::vector<Row>& rows, const std::vector<Index>& position,
                        Index n_primal) {
  const Index n_rows = static_cast<Index>(rows.size()), N = n_primal + n_rows;
  std::vector<Triplet> kkt;
  kkt.reserve(h.size() + 5 * rows.size());
  auto put = [&](Index i, Index j, double x) {
    const Index pi = position[i], pj = position[j];
    kkt.emplace_back(std::max(pi, pj), std::min(pi, pj), x);
  };
  for (const Triplet& x : h) put(x.row(), x.col(), x.value());
  for (Index c = 0; c < n_rows; ++c) {
    for (int i = 0; i < rows[c].n; ++i) put(n_primal + c, rows[c].var[i], rows[c].coef[i]);
    put(n_primal + c, n_primal + c, -kRegularization);
  }
  std::vector<Triplet>().swap(h);
  SparseMatrix K(N, N);
  K.setFromTriplets(kkt.begin(), kkt.end());
  return K;
}

// Solve, then refine against the system without regularization until the
// residual is at rounding level (usually one step), or stops shrinking
// (rounding in the factors sets a floor near 1e-12; a step that does not
// halve the residual only costs a solve). `is_row`: 1 at the constraints'
// positions.
Eigen::VectorXd refined_solve(const SparseMatrix& K, const SupernodalLdlt& ldlt, const Eigen::VectorXd& b,
                              const Eigen::VectorXd& is_row) {
  Eigen::VectorXd x = ldlt.solve(b);
  const double b_norm = std::max(b.lpNorm<Eigen::Infinity>(), 1e-300);
  double previous = std::numeric_limits<double>::infinity();
  for (int step = 0; step < 3; ++step) {
    Eigen::VectorXd residual = b - K.selfadjointView<Eigen::Lower>() * x;
    residual -= kRegularization * is_row.cwiseProduct(x);  // undo -d on the constraint block
    const double r = residual.lpNorm<Eigen::Infinity>();
    if (r <= 1e-12 * b_norm || !(r < 0.5 * previous)) break;
    previous = r;
    x += ldlt.solve(residual);
  }
  return x;
}

// Transitions: the rotation from the combed matching, the translation from
// the two copies of the edge's ends (equal up to the residual); returns the
// largest disagreement of the two.
double transitions(const Surface& surface, const CutGraph& cut, Parameterization& out) {
  const TriangleMesh& mesh = surface.mesh;
  const MeshTopology& topo = surface.topology;
  double residual = 0;
  out.transition.assign(topo.num_edges(), Transition{});
  for (Index e = 0; e < topo.num_edges(); ++e) {
    if (!cut.on_cut[e]) continue;
    const auto [t0, t1] = topo.edge_triangles[e];
    Transition& tr = out.transition[e];
    tr.r = mod4(4 - cut.combed_matching[e]);
    Vec2 ends[2];
    for (int k = 0; k < 2; ++k) {
      const Index v = topo.edges[e][k];
      ends[k] = out.uv[t1][corner_of(mesh.triangles[t1], v)] - turn(out.uv[t0][corner_of(mesh.triangles[t0], v)], tr.r);
    }
    tr.tr = 0.5 * (ends[0] + ends[1]);
    residual = std::max(residual, (ends[0] - ends[1]).norm());
  }
  return residual;
}

// Loops: the value of the across-coordinate at both ends of each segment;
// returns the largest disagreement of the two.
double loop_values(const Surface& surface, const std::vector<LoopPath>& loops, Parameterization& out) {
  double residual = 0;
  out.loop_value.resize(loops.size());
  out.loop_points_uv.resize(loops.size());
  for (size_t l = 0; l < loops.size(); ++l) {
    const LoopPath& lp = loops[l];
    for (size_t k = 0; k < lp.segments.size(); ++k) {
      const PathSegment& g = lp.segments[k];
      const auto& c = out.uv[g.triangle];
      const Vec3 bp = barycentric_in(surface, lp.path, g.from, g.triangle);
      const Vec3 bq = barycentric_in(surface, lp.path, g.to, g.triangle);
      const std::array<Vec2, 2> ends{bp[0] * c[0] + bp[1] * c[1] + bp[2] * c[2], bq[0] * c[0] + bq[1] * c[1] + bq[2] * c[2]};
      const int axis = out.loop_axis[l][k];
      out.loop_points_uv[l].push_back(ends);
      out.loop_value[l].push_back(0.5 * (ends[0][axis] + ends[1][axis]));
      residual = std::max(residual, std::abs(ends[0][axis] - ends[1][axis]));
    }
  }
  return residual;
}

}  // namespace

Vec2 Transition::apply(const Vec2& p) const { return turn(p, r) + tr; }

std::vector<LoopMeeting> contradicting_meetings(const Surface& surface, const CrossField& field,
                                                const std::vector<LoopPath>& loops) {
  const CutGraph cut = cut_to_disk(surface, field);
  std::vector<Vec3> f, n;
  combed_frames(surface, field, cut, f, n);
  return meetings_of(surface, cut, loops, loop_axes(f, n, loops));
}

std::vector<Index> vertex_elimination_order(const Surface& surface) {
  return nested_dissection_order(surface.topology.vertex_neighbours);
}

Parameterization parameterize(const Surface& surface, const CrossField& field, const std::vector<LoopPath>& loops,
                              const std::vector<Index>& vertex_order) {
  const auto start = Clock::now();
  const TriangleMesh& mesh = surface.mesh;
  const Index F = mesh.num_triangles();
  if (F == 0) throw InputError("the surface has no triangles to parameterize");
  if (static_cast<Index>(field.direction.size()) != F || static_cast<Index>(field.frame_x.size()) != F)
    throw std::invalid_argument("parameterize: the cross field does not belong to this surface");
  for (const LoopPath& lp : loops)
    for (const PathSegment& g : lp.segments)
      if (g.triangle < 0 || g.triangle >= F || g.from < 0 || g.to < 0 ||
          g.from >= static_cast<Index>(lp.path.points.size()) || g.to >= static_cast<Index>(lp.path.points.size()))
        throw std::invalid_argument("parameterize: a loop segment refers to a triangle or point that does not exist");

  Parameterization out;
  auto lap = [&, last = start](const char* stage) mutable {
    const auto now = Clock::now();
    out.timings.emplace_back(stage, millis(last, now));
    last = now;
  };

  // (1, 2) Cut graph and combed field; loops whose meetings the field
  // cannot align with both are refused before the solve.
  const CutGraph cut = cut_to_disk(surface, field);
  std::vector<Vec3> f, n;
  combed_frames(surface, field, cut, f, n);
  out.comb = cut.comb;
  out.on_cut = cut.on_cut;
  out.cut_ends = cut.cut_ends;
  out.loop_axis = loop_axes(f, n, loops);
  if (const std::vector<LoopMeeting> m = meetings_of(surface, cut, loops, out.loop_axis); !m.empty())
    throw_meeting(surface, m.front());
  lap("cut and comb");

  const Unknowns unknowns = unknowns_of(cut);
  const Index n_primal = unknowns.n_primal;
  const std::vector<Row> rows = constraint_rows(surface, cut, loops, out.loop_axis, unknowns);
  const Index n_rows = static_cast<Index>(rows.size()), N = n_primal + n_rows;
  std::vector<Triplet> h;
  Eigen::VectorXd rhs;
  energy(surface, cut, f, n, unknowns, n_rows, h, rhs);
  lap("energy and constraints");

  const std::vector<Index> position = elimination_positions(surface, cut, unknowns, rows, vertex_order);
  lap("elimination order");

  const SparseMatrix K = kkt_matrix(h, rows, position, n_primal);
  Eigen::VectorXd b(N);
  for (Index i = 0; i < N; ++i) b[position[i]] = rhs[i];
  lap("KKT system");

  SupernodalLdlt ldlt;
  ldlt.compute(K);
  lap("factorization");

  Eigen::VectorXd is_row = Eigen::VectorXd::Zero(N);
  for (Index c = 0; c < n_rows; ++c) is_row[position[n_primal + c]] = 1;
  const Eigen::VectorXd x = refined_solve(K, ldlt, b, is_row);
  lap("solve");

  // Output: per triangle its corners' (u, v), fold-overs, transitions, the
  // loops' values, and the constraints' residual.
  auto coordinates = [&](Index w) {
    return unknowns.slot[w] < 0 ? Vec2::Zero()
                                : Vec2(x[position[unknowns.var(w, 0)]], x[position[unknowns.var(w, 1)]]);
  };
  out.uv.resize(F);
  out.flipped.assign(F, 0);
  for (Index t = 0; t < F; ++t) {
    for (int i = 0; i < 3; ++i) out.uv[t][i] = coordinates(cut.wedge_of(t, i));
    const Vec2 e1 = out.uv[t][1] - out.uv[t][0], e2 = out.uv[t][2] - out.uv[t][0];
    if (e1.x() * e2.y() - e1.y() * e2.x() < 0) out.flipped[t] = 1, ++out.fold_overs;
  }
  const double residual = std::max(transitions(surface, cut, out), loop_values(surface, loops, out));
  out.constraint_residual = residual;
  if (!(residual <= kResidualTolerance)) {
    std::ostringstream m;
    m << "the loops' isocurve and transition constraints cannot be met together (residual " << residual
      << " of the model size after the solve)";
    throw InputError(m.str());
  }
  lap("output");
  out.solve_ms = millis(start, Clock::now());
  return out;
}

}  // namespace stripweave
