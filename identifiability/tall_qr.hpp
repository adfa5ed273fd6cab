// The triangular factor of a tall matrix, row block by row block: R (cols x cols, upper
// triangular) with R^T R = A^T A, without holding A. Each block is stacked under the running R and
// reduced by Householder QR, so the working set stays in cache and the cost is O(rows cols^2),
// linear in the rows. The singular values, the unpivoted QR's |R_jj| and the least-squares
// solution of A follow from R (orthogonal invariance); appending the right-hand side as a last
// column gives Q^T y in R's last column and the residual norm in its corner.
#pragma once

#include <Eigen/Core>

namespace dynid {

class TallQr {
 public:
  /// `block_rows` rows are buffered before each reduction.
  explicit TallQr(Eigen::Index cols, Eigen::Index block_rows = 1024);
  using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  /// Appends rows (any number, cols() columns).
  void add(const Eigen::Ref<const Eigen::MatrixXd>& rows);
  void addRowMajor(const Eigen::Ref<const RowMajorMatrix>& rows);
  /// Appends one row.
  void addRow(const Eigen::Ref<const Eigen::RowVectorXd>& row);
  /// R so far: cols x cols, upper triangular; rows beyond those added are zero.
  Eigen::MatrixXd r();
  Eigen::Index cols() const { return cols_; }
  Eigen::Index rowsAdded() const { return added_; }

 private:
  void reduce();
  template <class Rows>
  void addRows(const Rows& rows);
  Eigen::Index cols_;
  Eigen::MatrixXd stack_;    // the running R on top, then buffered rows
  Eigen::Index filled_ = 0;  // rows of stack_ in use
  Eigen::Index added_ = 0;
  bool pending_ = false;
  Eigen::VectorXd h_coeffs_,
      temp_;  // the reduction's workspace  // rows added since the last reduction
};

}  // namespace dynid
