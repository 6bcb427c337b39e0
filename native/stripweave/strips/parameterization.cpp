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
// without harm. It is factored once (a supernodal LDL^T, below) in a
// fill-reducing order of the unknowns in which every constraint row comes
// right after the last of its unknowns: a constraint is never a pivot before
// its unknowns (which would turn d into a 1/d-sized update), and a redundant
// one meets a pivot near -d with a row that is zero up to rounding. A step
// of iterative refinement against the system without d removes what d and
// rounding leave in the constraints.
#include "stripweave/strips/parameterization.h"

#include "stripweave/core/error.h"
#include "stripweave/strips/cut_graph.h"

#include <Eigen/Dense>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace stripweave {

namespace {

using Clock = std::chrono::steady_clock;
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Triplet = Eigen::Triplet<double, int>;

constexpr double kRegularization = 1e-12;
// Constraint residuals above this (normalized units: the model's diagonal
// is 1) mean the solve failed; the contract promises 1e-9.
constexpr double kResidualTolerance = 1e-9;

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

// --- A supernodal LDL^T for the KKT system ------------------------------------
//
// Eigen's SimplicialLDLT works column by column through scattered memory; at
// 30K triangles (a million and a half nonzeros in L, some 400 million flops
// where odd transitions tie the two sheets of u and v together) that alone
// took 80-160 ms. This multifrontal variant does the same arithmetic in
// dense blocks (Eigen's matrix products), two to three times faster. It
// factors in the given order (up to an equivalent postorder of the
// elimination tree) without pivoting, which is safe for the quasi-definite
// KKT matrix in an order that puts every constraint after its unknowns.
//
//   symbolic  elimination tree and column counts of L (Liu's algorithm, as
//             in Eigen); postorder, so that every subtree is a contiguous
//             range of columns; fundamental supernodes (columns with nested
//             structure), merged with their parent while the explicit zeros
//             this adds stay small (CHOLMOD's default rules); each front's
//             rows.
//   numeric   per supernode, its front: the matrix's columns plus the
//             children's Schur complements (extend-add), a blocked partial
//             LDL^T of its leading columns, and the Schur complement of the
//             rest, which goes to the parent.
class SupernodalLdlt {
 public:
  // `lower`: the lower triangle of the symmetric matrix, column-major.
  void compute(const SparseMatrix& lower);
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  struct Supernode {
    int first = 0, width = 0;
    std::vector<int> rows;  // the front's rows: its own columns, then the rows below, ascending
    Eigen::MatrixXd L;      // rows.size() x width: unit lower L11 over L21
  };
  int n_ = 0;
  std::vector<int> post_;  // position in the postorder -> index in the given order
  std::vector<Supernode> supernodes_;
  Eigen::VectorXd d_;
};

// The elimination tree of a symmetric matrix given by its upper triangle
// (column k: the rows i < k of row k of the lower triangle), and the number of
// off-diagonal nonzeros in each column of L: row k of L is the union of the
// tree paths from the nonzeros of row k of A up to k.
void elimination_tree(const SparseMatrix& upper, std::vector<int>& parent, std::vector<int>& count) {
  const int n = upper.cols();
  parent.assign(n, -1);
  count.assign(n, 0);
  std::vector<int> tag(n);
  for (int k = 0; k < n; ++k) {
    tag[k] = k;
    for (SparseMatrix::InnerIterator it(upper, k); it; ++it)
      for (int i = it.index(); i < k && tag[i] != k; i = parent[i]) {
        if (parent[i] == -1) parent[i] = k;
        ++count[i];
        tag[i] = k;
      }
  }
}

void SupernodalLdlt::compute(const SparseMatrix& given) {
  n_ = given.cols();
  std::vector<int> parent, count;
  SparseMatrix upper = given.transpose();
  elimination_tree(upper, parent, count);

  // Postorder (children in increasing order, iteratively).
  std::vector<int> head(n_, -1), next(n_, -1), stack;
  for (int j = n_ - 1; j >= 0; --j)
    if (parent[j] >= 0) next[j] = head[parent[j]], head[parent[j]] = j;
  post_.clear();
  post_.reserve(n_);
  for (int root = 0; root < n_; ++root) {
    if (parent[root] != -1) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const int j = stack.back();
      if (head[j] >= 0) {
        stack.push_back(head[j]);
        head[j] = next[head[j]];
      } else {
        stack.pop_back();
        post_.push_back(j);
      }
    }
  }
  SparseMatrix lower;
  bool identity = true;
  for (int k = 0; k < n_ && identity; ++k) identity = post_[k] == k;
  if (identity) {
    lower = given;
  } else {
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p(n_);
    for (int k = 0; k < n_; ++k) p.indices()[post_[k]] = k;
    lower.resize(n_, n_);
    lower.selfadjointView<Eigen::Lower>() = given.selfadjointView<Eigen::Lower>().twistedBy(p);
    upper = lower.transpose();
    elimination_tree(upper, parent, count);
  }

  // Supernodes: a column joins the previous one if it is its only child and
  // its structure is the child's minus the child itself; then a group is
  // merged into the following one (its parent) while the merged block keeps
  // few explicit zeros relative to its size.
  std::vector<int> children(n_, 0);
  for (int j = 0; j < n_; ++j)
    if (parent[j] >= 0) ++children[parent[j]];
  struct Group {
    int first, width, height;
    double storage, zeros;  // entries of the trapezoidal block, and how many are structural zeros
  };
  auto trapezoid = [](double w, double h) { return w * h - w * (w - 1) / 2; };
  std::vector<Group> groups;
  for (int j = 0; j < n_;) {
    int end = j + 1;
    while (end < n_ && parent[end - 1] == end && count[end - 1] == count[end] + 1 && children[end] == 1) ++end;
    Group g{j, end - j, count[j] + 1, 0, 0};
    g.storage = trapezoid(g.width, g.height);
    while (!groups.empty()) {
      const Group& c = groups.back();
      if (c.first + c.width != g.first || parent[g.first - 1] != g.first) break;
      const int w = c.width + g.width, h = c.width + g.height;
      const double storage = trapezoid(w, h);
      const double zeros = storage - (c.storage - c.zeros) - (g.storage - g.zeros);
      const double z = zeros / storage;
      if (!(w <= 4 || (w <= 16 && z < 0.8) || (w <= 48 && z < 0.1) || z < 0.05)) break;
      g = Group{c.first, w, h, storage, zeros};
      groups.pop_back();
    }
    groups.push_back(g);
    j = end;
  }
  const int ns = static_cast<int>(groups.size());
  std::vector<int> group_of(n_);
  for (int s = 0; s < ns; ++s)
    for (int j = groups[s].first; j < groups[s].first + groups[s].width; ++j) group_of[j] = s;
  std::vector<std::vector<int>> kids(ns);
  for (int s = 0; s < ns; ++s) {
    const int last = groups[s].first + groups[s].width - 1;
    if (parent[last] >= 0) kids[group_of[parent[last]]].push_back(s);
  }

  // Each front's rows: its columns, the matrix's rows below them, and the
  // rows of its children's Schur complements.
  supernodes_.assign(ns, Supernode{});
  std::vector<int> mark(n_, -1);
  for (int s = 0; s < ns; ++s) {
    Supernode& S = supernodes_[s];
    S.first = groups[s].first;
    S.width = groups[s].width;
    const int last = S.first + S.width - 1;
    for (int j = S.first; j <= last; ++j) S.rows.push_back(j), mark[j] = s;
    for (int j = S.first; j <= last; ++j)
      for (SparseMatrix::InnerIterator it(lower, j); it; ++it)
        if (mark[it.index()] != s) mark[it.index()] = s, S.rows.push_back(it.index());
    for (int c : kids[s]) {
      const Supernode& C = supernodes_[c];
      for (size_t a = C.width; a < C.rows.size(); ++a)
        if (mark[C.rows[a]] != s) mark[C.rows[a]] = s, S.rows.push_back(C.rows[a]);
    }
    std::sort(S.rows.begin() + S.width, S.rows.end());
  }

  // Numeric factorization, front by front.
  d_.resize(n_);
  std::vector<Eigen::MatrixXd> schur(ns);
  std::vector<int> local(n_), index;
  constexpr int kBlock = 32;
  for (int s = 0; s < ns; ++s) {
    Supernode& S = supernodes_[s];
    const int h = static_cast<int>(S.rows.size()), w = S.width;
    for (int a = 0; a < h; ++a) local[S.rows[a]] = a;
    Eigen::MatrixXd F = Eigen::MatrixXd::Zero(h, h);
    for (int j = S.first; j < S.first + w; ++j)
      for (SparseMatrix::InnerIterator it(lower, j); it; ++it) F(local[it.index()], j - S.first) += it.value();
    for (int c : kids[s]) {
      const Supernode& C = supernodes_[c];
      const Eigen::MatrixXd& U = schur[c];
      const int u = static_cast<int>(U.rows());
      index.resize(u);
      for (int a = 0; a < u; ++a) index[a] = local[C.rows[C.width + a]];
      for (int col = 0; col < u; ++col) {
        double* target = &F(0, index[col]);
        for (int a = col; a < u; ++a) target[index[a]] += U(a, col);
      }
      schur[c].resize(0, 0);
    }
    // Blocked right-looking LDL^T of the leading w columns; the trailing
    // block ends up as the Schur complement.
    for (int kb = 0; kb < w; kb += kBlock) {
      const int ke = std::min(w, kb + kBlock);
      for (int k = kb; k < ke; ++k) {
        const double d = F(k, k);
        if (!(d != 0) || !std::isfinite(d))
          throw std::runtime_error("parameterize: zero pivot in the KKT factorization");
        d_[S.first + k] = d;
        for (int j = k + 1; j < ke; ++j)
          F.col(j).segment(j, h - j).noalias() -= F.col(k).segment(j, h - j) * (F(j, k) / d);
        F.col(k).segment(k + 1, h - k - 1) /= d;
      }
      if (ke < h) {
        const int r = h - ke;
        const Eigen::MatrixXd ld = F.block(ke, kb, r, ke - kb) * d_.segment(S.first + kb, ke - kb).asDiagonal();
        F.bottomRightCorner(r, r).triangularView<Eigen::Lower>() -= ld * F.block(ke, kb, r, ke - kb).transpose();
      }
    }
    S.L = F.leftCols(w);
    if (h > w) schur[s] = F.bottomRightCorner(h - w, h - w);
  }
}

Eigen::VectorXd SupernodalLdlt::solve(const Eigen::VectorXd& b) const {
  Eigen::VectorXd x(n_), t;
  for (int k = 0; k < n_; ++k) x[k] = b[post_[k]];
  for (const Supernode& S : supernodes_) {  // L y = b
    const int h = static_cast<int>(S.rows.size()), w = S.width;
    auto xs = x.segment(S.first, w);
    S.L.topRows(w).triangularView<Eigen::UnitLower>().solveInPlace(xs);
    if (h > w) {
      t.noalias() = S.L.bottomRows(h - w) * xs;
      for (int a = 0; a < h - w; ++a) x[S.rows[w + a]] -= t[a];
    }
  }
  x.array() /= d_.array();  // D z = y
  for (auto it = supernodes_.rbegin(); it != supernodes_.rend(); ++it) {  // L^T x = z
    const Supernode& S = *it;
    const int h = static_cast<int>(S.rows.size()), w = S.width;
    auto xs = x.segment(S.first, w);
    if (h > w) {
      t.resize(h - w);
      for (int a = 0; a < h - w; ++a) t[a] = x[S.rows[w + a]];
      xs.noalias() -= S.L.bottomRows(h - w).transpose() * t;
    }
    S.L.topRows(w).triangularView<Eigen::UnitLower>().transpose().solveInPlace(xs);
  }
  Eigen::VectorXd out(n_);
  for (int k = 0; k < n_; ++k) out[post_[k]] = x[k];
  return out;
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

[[noreturn]] void throw_meeting(const Surface& s, const std::vector<LoopPath>& loops, const SegmentRef& a,
                               const SegmentRef& b, const Vec3& where) {
  std::ostringstream m;
  if (a.loop == b.loop)
    m << "loop " << a.loop << " meets itself";
  else
    m << "loops " << a.loop << " and " << b.loop << " meet";
  m << " near " << model_point(s, where)
    << " running in the same direction of the cross field: both would have to be isocurves of the same coordinate "
       "there, so the strips would collapse; loops must cross transversally";
  throw InputError(m.str());
}

void check_meetings(const Surface& s, const CutGraph& cut, const std::vector<LoopPath>& loops,
                    const std::vector<std::vector<int>>& axis) {
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
          throw_meeting(s, loops, ra, rb, (mesh.positions[f[0]] + mesh.positions[f[1]] + mesh.positions[f[2]]) / 3);
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
            throw_meeting(s, loops, at[a].ref, at[b].ref, mesh.positions[v]);
    }
    i = j;
  }
}

}  // namespace

Vec2 Transition::apply(const Vec2& p) const { return turn(p, r) + tr; }

Parameterization parameterize(const Surface& surface, const CrossField& field, const std::vector<LoopPath>& loops) {
  const auto start = Clock::now();
  const TriangleMesh& mesh = surface.mesh;
  const MeshTopology& topo = surface.topology;
  const Index F = mesh.num_triangles(), E = topo.num_edges();
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

  // --- (1, 2) Cut graph and combed field ---------------------------------------
  const CutGraph cut = cut_to_disk(surface, field);
  std::vector<Vec3> f(F), n(F);
  for (Index t = 0; t < F; ++t) {
    n[t] = unit_normal(mesh, t);
    f[t] = combed_direction(surface, field, cut, t);
  }
  out.comb = cut.comb;
  out.on_cut = cut.on_cut;
  out.cut_ends = cut.cut_ends;

  // The coordinate across each loop segment: where the loop runs along the
  // combed field it is an isocurve of v, where it runs along f^perp of u.
  out.loop_axis.resize(loops.size());
  for (size_t l = 0; l < loops.size(); ++l)
    for (const PathSegment& g : loops[l].segments) {
      const Index t = g.triangle;
      const double along_u = std::abs(g.direction.dot(f[t])), along_v = std::abs(g.direction.dot(n[t].cross(f[t])));
      out.loop_axis[l].push_back(along_u >= along_v ? 1 : 0);
    }
  check_meetings(surface, cut, loops, out.loop_axis);
  lap("cut and comb");

  // --- Unknowns -------------------------------------------------------------
  const Index W = cut.num_wedges();
  std::vector<Index> slot(W, 0);  // wedge -> its index among the free wedges, or -1 if pinned
  for (Index c = 0; c < cut.num_components(); ++c) slot[cut.wedge_of(cut.tree_root[c], 0)] = -1;
  Index free_wedges = 0;
  for (Index w = 0; w < W; ++w)
    if (slot[w] == 0) slot[w] = free_wedges++;
  const Index n_primal = 2 * free_wedges;
  auto var = [&](Index w, int axis) -> Index { return slot[w] < 0 ? -1 : slot[w] + axis * free_wedges; };

  // --- Constraints -------------------------------------------------------------
  std::vector<Row> rows;
  for (Index e = 0; e < E; ++e) {
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
      row.add(var(a1, k), 1);
      row.add(var(a0, source(r, k)), -sign(r, k));
      row.add(var(b1, k), -1);
      row.add(var(b0, source(r, k)), sign(r, k));
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
      for (int c = 0; c < 3; ++c) row.add(var(cut.wedge_of(g.triangle, c), out.loop_axis[l][k]), bp[c] - bq[c]);
      row.tidy();
      if (row.n > 0) rows.push_back(row);
    }
  }
  const Index n_rows = static_cast<Index>(rows.size());

  // --- Energy: cotangent Laplacian and the field's divergence -----------------------
  // In triangle t the hat function of corner i has the constant gradient
  // n x (p[i+2] - p[i+1]) / 2A, so A grad(phi_i).grad(phi_j) is the usual
  // cotangent weight and A f.grad(phi_i) = f.(n x e_i) / 2.
  std::vector<Triplet> h;
  h.reserve(9 * 2 * static_cast<size_t>(F));
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_primal + n_rows);
  for (Index t = 0; t < F; ++t) {
    const Tri& tri = mesh.triangles[t];
    const Vec3 area2 = triangle_normal_area2(mesh, t);
    const double a2 = area2.norm();
    if (!(a2 > 1e-24)) continue;  // degenerate: no gradient to fit
    std::array<Vec3, 3> g;        // 2A grad(phi_i)
    for (int i = 0; i < 3; ++i)
      g[i] = n[t].cross(mesh.positions[tri[(i + 2) % 3]] - mesh.positions[tri[(i + 1) % 3]]);
    const Vec3 fu = f[t], fv = n[t].cross(f[t]);
    for (int i = 0; i < 3; ++i) {
      const Index w = cut.wedge_of(t, i);
      for (int axis = 0; axis < 2; ++axis) {
        const Index x = var(w, axis);
        if (x < 0) continue;
        rhs[x] += 0.5 * (axis == 0 ? fu : fv).dot(g[i]);
        for (int j = 0; j < 3; ++j) {
          const Index y = var(cut.wedge_of(t, j), axis);
          if (y >= 0 && y <= x) h.emplace_back(x, y, g[i].dot(g[j]) / (2 * a2));
        }
      }
    }
  }

  // --- Elimination order -----------------------------------------------------
  // Minimum degree over the pattern of H plus what eliminating a constraint
  // couples (C^T C), then each constraint right after its last unknown.
  // (Ordering the wedges alone, u and v side by side, is three times faster
  // but blind to how transitions with odd quarter turns tie the u of one
  // side of the cut to the v of the other: up to twice the fill.)
  std::vector<Index> position(n_primal + n_rows);
  {
    std::vector<Triplet> pattern;
    pattern.reserve(h.size() + 16 * rows.size());
    for (const Triplet& x : h) pattern.emplace_back(x.row(), x.col(), 1.0);
    for (const Row& row : rows)
      for (int i = 0; i < row.n; ++i)
        for (int j = 0; j < row.n; ++j) pattern.emplace_back(row.var[i], row.var[j], 1.0);
    SparseMatrix p(n_primal, n_primal);
    p.setFromTriplets(pattern.begin(), pattern.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
    Eigen::AMDOrdering<int>()(p, order);  // order.indices()[k] = the k-th unknown to eliminate
    std::vector<Index> rank(n_primal);
    for (Index k = 0; k < n_primal; ++k) rank[order.indices()[k]] = k;
    std::vector<std::vector<Index>> after(n_primal);
    for (Index c = 0; c < n_rows; ++c) {
      Index last = 0;
      for (int i = 0; i < rows[c].n; ++i) last = std::max(last, rank[rows[c].var[i]]);
      after[last].push_back(c);
    }
    Index next = 0;
    for (Index k = 0; k < n_primal; ++k) {
      position[order.indices()[k]] = next++;
      for (Index c : after[k]) position[n_primal + c] = next++;
    }
  }

  // --- The KKT system, lower triangle, in elimination order ---------------------------
  const Index N = n_primal + n_rows;
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
  SparseMatrix K(N, N);
  K.setFromTriplets(kkt.begin(), kkt.end());
  Eigen::VectorXd b(N);
  for (Index i = 0; i < N; ++i) b[position[i]] = rhs[i];
  lap("assembly and ordering");

  SupernodalLdlt ldlt;
  ldlt.compute(K);
  lap("factorization");

  // Solve, then refine against the system without regularization until the
  // residual is at rounding level (usually one step).
  Eigen::VectorXd x = ldlt.solve(b);
  Eigen::VectorXd is_row = Eigen::VectorXd::Zero(N);
  for (Index c = 0; c < n_rows; ++c) is_row[position[n_primal + c]] = 1;
  const double b_norm = std::max(b.lpNorm<Eigen::Infinity>(), 1e-300);
  for (int step = 0; step < 3; ++step) {
    Eigen::VectorXd residual = b - K.selfadjointView<Eigen::Lower>() * x;
    residual -= kRegularization * is_row.cwiseProduct(x);  // undo -d on the constraint block
    if (residual.lpNorm<Eigen::Infinity>() <= 1e-12 * b_norm) break;
    x += ldlt.solve(residual);
  }
  lap("solve");

  // --- Output -----------------------------------------------------------------
  auto coordinates = [&](Index w) {
    return slot[w] < 0 ? Vec2::Zero() : Vec2(x[position[var(w, 0)]], x[position[var(w, 1)]]);
  };
  out.uv.resize(F);
  out.flipped.assign(F, 0);
  for (Index t = 0; t < F; ++t) {
    for (int i = 0; i < 3; ++i) out.uv[t][i] = coordinates(cut.wedge_of(t, i));
    const Vec2 e1 = out.uv[t][1] - out.uv[t][0], e2 = out.uv[t][2] - out.uv[t][0];
    if (e1.x() * e2.y() - e1.y() * e2.x() < 0) out.flipped[t] = 1, ++out.fold_overs;
  }

  // Transitions: the rotation from the combed matching, the translation
  // from the two copies of the edge's ends (equal up to the residual).
  double residual = 0;
  out.transition.assign(E, Transition{});
  for (Index e = 0; e < E; ++e) {
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

  // Loops: the value of the across-coordinate at both ends of each segment.
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
