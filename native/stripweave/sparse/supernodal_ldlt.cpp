// SupernodalLdlt (see the header).
#include "stripweave/sparse/supernodal_ldlt.h"

#include "stripweave/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <thread>


namespace stripweave {

namespace {

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

}  // namespace

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

  // Numeric factorization, front by front. Fronts in disjoint subtrees of
  // the elimination tree are independent (a front needs only its children's
  // Schur complements), and nested dissection makes the tree split early
  // into two halves of similar work: those run on two threads, then the
  // fronts above them on this one. Each front's arithmetic is the same
  // whichever thread runs it, so the factors do not depend on the threads.
  d_.resize(n_);
  std::vector<Eigen::MatrixXd> schur(ns);
  auto factor_front = [&](int s, std::vector<int>& local, std::vector<int>& index) {
    constexpr int kBlock = 32;
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
  };

  // Work per subtree (its fronts' h^2 w) and where it starts: in postorder
  // the subtree of front s is the range [first[s], s].
  std::vector<double> work(ns);
  std::vector<int> first(ns), front_parent(ns, -1);
  for (int s = 0; s < ns; ++s) {
    const double h = static_cast<double>(supernodes_[s].rows.size());
    work[s] = h * h * supernodes_[s].width;
    first[s] = s;
    for (int c : kids[s]) work[s] += work[c], first[s] = std::min(first[s], first[c]), front_parent[c] = s;
  }
  std::vector<int> roots;
  double total = 0;
  for (int s = 0; s < ns; ++s)
    if (front_parent[s] < 0) roots.push_back(s), total += work[s];
  auto run_subtree = [&](int root, std::vector<int>& local, std::vector<int>& index) {
    for (int s = first[root]; s <= root; ++s) factor_front(s, local, index);
  };
  std::vector<int> local(n_), index;
  constexpr double kParallelWork = 2e7;  // below this a thread costs more than it saves
  if (total < kParallelWork || usable_cores() < 2) {
    for (int s = 0; s < ns; ++s) factor_front(s, local, index);
    return;
  }
  // Split the heaviest subtree while it holds more than half the work; its
  // own front waits for the second phase.
  std::vector<int> frontier = roots, top;
  for (;;) {
    auto heaviest = std::max_element(frontier.begin(), frontier.end(), [&](int a, int b) { return work[a] < work[b]; });
    if (work[*heaviest] <= 0.55 * total || kids[*heaviest].empty()) break;
    const int s = *heaviest;
    frontier.erase(heaviest);
    top.push_back(s);
    frontier.insert(frontier.end(), kids[s].begin(), kids[s].end());
  }
  // Two bins of subtrees, heaviest first into the lighter bin.
  std::sort(frontier.begin(), frontier.end(), [&](int a, int b) { return work[a] > work[b] || (work[a] == work[b] && a < b); });
  std::vector<int> bin[2];
  double load[2] = {0, 0};
  for (int s : frontier) {
    const int b = load[0] <= load[1] ? 0 : 1;
    bin[b].push_back(s), load[b] += work[s];
  }
  Eigen::initParallel();
  std::exception_ptr failed;
  std::thread helper([&] {
    try {
      std::vector<int> helper_local(n_), helper_index;
      for (int root : bin[1]) run_subtree(root, helper_local, helper_index);
    } catch (...) {
      failed = std::current_exception();
    }
  });
  try {
    for (int root : bin[0]) run_subtree(root, local, index);
  } catch (...) {
    helper.join();
    throw;
  }
  helper.join();
  if (failed) std::rethrow_exception(failed);
  std::sort(top.begin(), top.end());  // postorder: children first
  for (int s : top) factor_front(s, local, index);
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

}  // namespace stripweave
