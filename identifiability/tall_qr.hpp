// The triangular factor of a tall matrix, row block by row block: R (cols x cols, upper
// triangular) with R^T R = A^T A, without holding A. Buffered rows are reduced into the running R
// by Householder reflections that touch only R's row and the buffered rows (R's zeros are never
// visited), 128 rows at a time so that the columns being updated stay in the L1 cache: 2 rows
// cols^2 flops, linear in the rows. With AVX2 and FMA two reflectors are applied in one pass over
// the rows (compact WY), which halves the memory traffic per flop. The singular values, the
// unpivoted QR's |R_jj| and the least-squares solution of A follow from R (orthogonal
// invariance); appending the right-hand side as a last column gives Q^T y in R's last column and
// the residual norm in its corner.
//
// The result depends only on the rows, their order and block_rows, not on how they were handed
// over (one at a time, in chunks of any size). A column that is zero in every row stays exactly
// zero in R.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace dynid {

class TallQr {
 public:
  /// The reduction's machine code: AVX2 and FMA where the CPU has them (kAuto), or the portable
  /// SSE2 one. They round differently (FMA), so one run's R is the same bits for any thread count
  /// and any blocking of the rows, but may differ in the last bits between CPUs.
  enum class Kernel { kAuto, kPortable, kAvx2 };
  /// Whether this CPU runs the AVX2 kernel.
  static bool avx2Available();

  /// `block_rows` rows are buffered before each reduction. Throws InputError for kAvx2 on a CPU
  /// without it.
  explicit TallQr(Eigen::Index cols, Eigen::Index block_rows = 1024, Kernel kernel = Kernel::kAuto);
  using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  /// Appends rows (any number, cols() columns).
  void add(const Eigen::Ref<const Eigen::MatrixXd>& rows);
  void addRowMajor(const Eigen::Ref<const RowMajorMatrix>& rows);
  /// Appends one row.
  void addRow(const Eigen::Ref<const Eigen::RowVectorXd>& row);

  /// Rows written in place by a caller that computes them, without a copy: freeRows() is the
  /// buffer's next free row (row-major, cols() values a row, rowStride() apart; the entries after
  /// the cols() values are padding and must be left as they are), room() how many rows fit before
  /// the buffer is reduced. After writing k rows, commitRows(k) appends them as addRowMajor would.
  double* freeRows() { return block_.data() + filled_ * stride_; }
  Eigen::Index room() const { return block_rows_ - filled_; }
  Eigen::Index rowStride() const { return stride_; }
  /// Throws InputError unless 0 <= k <= room().
  void commitRows(Eigen::Index k);
  /// Reduces the buffered rows now (r() does too), so that the next row starts a new block.
  void flush();
  /// Starts again with no rows (R zero), keeping its buffers: a factor per batch of a stream
  /// without allocating (and zeroing) the row buffer each time.
  void reset();
  /// R so far: cols x cols, upper triangular; rows beyond those added are zero (to rounding).
  Eigen::MatrixXd r();
  Eigen::Index cols() const { return cols_; }
  Eigen::Index rowsAdded() const { return added_; }

 private:
  void reduce();
  template <class Rows>
  void addRows(const Rows& rows);
  Eigen::Index cols_;
  Eigen::Index stride_;        // row stride of r_ and block_: cols_ plus zero padding for the tiles
  Eigen::Index block_rows_;    // rows buffered before a reduction
  std::vector<double> r_;      // R, row-major (stride_ per row), zero below the diagonal and after
  std::vector<double> block_;  // buffered rows, row-major (stride_ per row), zero padding
  std::vector<double> v_;      // the AVX2 kernel's two reflector vectors and its panel columns
  bool avx2_ = false;
  Eigen::Index filled_ = 0;  // rows of block_ in use
  Eigen::Index added_ = 0;
};

/// The triangular factor of two triangular factors' rows stacked: R (n x n, upper triangular) with
/// R^T R = A^T A + B^T B, A and B upper triangular and n x n (InputError otherwise), by Householder
/// reflections that visit only the triangles (LAPACK's triangular-pentagonal QR, tpqrt, with B
/// triangular): (2/3) n^3 flops, a fifth of reducing the 2n stacked rows as dense ones. A column
/// zero in both stays exactly zero; the same bits for the same inputs.
Eigen::MatrixXd stackedTriangularFactor(const Eigen::Ref<const Eigen::MatrixXd>& a,
                                        const Eigen::Ref<const Eigen::MatrixXd>& b);

}  // namespace dynid
