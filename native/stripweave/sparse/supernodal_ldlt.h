// SupernodalLdlt: a sparse LDL^T factorization without pivoting, for
// symmetric quasi-definite matrices (the KKT systems of the global
// parameterization, strips/parameterization.cpp).
//
// compute(lower)  Input: the lower triangle of a symmetric n x n matrix,
//                 column-major, already in the elimination order the caller
//                 wants (a fill-reducing order, sparse/nested_dissection.h,
//                 in which no pivot is structurally zero). Throws
//                 std::runtime_error on a zero or non-finite pivot.
// solve(b)        Output: x with A x = b, in the caller's order.
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
#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <vector>

namespace stripweave {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

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

}  // namespace stripweave
