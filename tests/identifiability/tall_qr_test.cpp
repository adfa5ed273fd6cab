#include "identifiability/tall_qr.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include <Eigen/QR>

#include "core/errors.hpp"

namespace dynid {
namespace {

// Householder QR is backward stable: R^T R matches A^T A to ~1e-15 relative per step; 1e-12 allows
// for the accumulation over hundreds of stacked reductions.
constexpr double kTolerance = 1e-12;

TEST(TallQr, TriangularFactorOfAnyBlockingEqualsTheWholeQr) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(2503, 7);
  const Eigen::HouseholderQR<Eigen::MatrixXd> whole(A);
  const Eigen::MatrixXd expected = whole.matrixQR().topRows(7).triangularView<Eigen::Upper>();
  for (Eigen::Index block : {1, 7, 64, 1024, 5000}) {
    TallQr factor(7, block);
    factor.add(A.topRows(1000));
    for (Eigen::Index r = 1000; r < 1100; ++r) factor.addRow(A.row(r));
    factor.add(A.bottomRows(A.rows() - 1100));
    const Eigen::MatrixXd R = factor.r();
    EXPECT_EQ(factor.rowsAdded(), A.rows());
    EXPECT_TRUE(R.isUpperTriangular());
    // R is unique up to the signs of its rows.
    EXPECT_LT((R.transpose() * R - A.transpose() * A).norm(),
              kTolerance * (A.transpose() * A).norm())
        << "block " << block;
    EXPECT_LT((R.diagonal().cwiseAbs() - expected.diagonal().cwiseAbs()).norm(),
              kTolerance * expected.norm())
        << "block " << block;
  }
}

TEST(TallQr, ResetStartsAgainAsANewFactorDoes) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(1500, 9), B = Eigen::MatrixXd::Random(700, 9);
  for (TallQr::Kernel kernel : {TallQr::Kernel::kPortable, TallQr::Kernel::kAuto}) {
    TallQr reused(9, 128, kernel);
    reused.add(A);
    reused.add(A.topRows(50));  // a part of a block left buffered
    reused.reset();
    EXPECT_EQ(reused.rowsAdded(), 0);
    reused.add(B);
    TallQr fresh(9, 128, kernel);
    fresh.add(B);
    EXPECT_EQ(reused.r(), fresh.r());  // the same rows, the same blocks: the same bits
  }
}

TEST(TallQr, AppendedRightHandSideSolvesLeastSquares) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(3000, 5);
  const Eigen::VectorXd y = Eigen::VectorXd::Random(3000);
  TallQr factor(6, 256);
  Eigen::MatrixXd augmented(3000, 6);
  augmented << A, y;
  factor.add(augmented);
  const Eigen::MatrixXd R = factor.r();
  const Eigen::VectorXd x =
      R.topLeftCorner(5, 5).triangularView<Eigen::Upper>().solve(R.col(5).head(5));
  const Eigen::VectorXd expected = A.householderQr().solve(y);
  EXPECT_LT((x - expected).norm(), kTolerance * expected.norm());
  // The corner is the residual norm.
  EXPECT_NEAR(std::abs(R(5, 5)), (A * expected - y).norm(), kTolerance * y.norm());
}

TEST(TallQr, FewerRowsThanColumnsAndNone) {
  TallQr empty(4);
  EXPECT_TRUE(empty.r().isZero());
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(2, 4);
  TallQr factor(4);
  factor.add(A);
  const Eigen::MatrixXd R = factor.r();
  EXPECT_TRUE(R.bottomRows(2).isZero());
  EXPECT_LT((R.transpose() * R - A.transpose() * A).norm(),
            kTolerance * (A.transpose() * A).norm());
  EXPECT_THROW(factor.add(Eigen::MatrixXd::Zero(1, 3)), InputError);
}

/// The kernels this CPU can run: the portable one, and the AVX2 one where it has AVX2 and FMA.
std::vector<TallQr::Kernel> kernels() {
  std::vector<TallQr::Kernel> out = {TallQr::Kernel::kPortable};
  if (TallQr::avx2Available()) out.push_back(TallQr::Kernel::kAvx2);
  return out;
}

TEST(TallQr, EveryKernelAndWidthFactorsTheMatrix) {
  // Widths 1 to 41 cover an odd last column, each tile width (4 to 16 columns) and several tiles;
  // 300 rows in blocks of 200 cover a partial group and a partial block.
  for (TallQr::Kernel kernel : kernels()) {
    for (Eigen::Index cols = 1; cols <= 41; ++cols) {
      const Eigen::MatrixXd A = Eigen::MatrixXd::Random(300, cols);
      TallQr factor(cols, 200, kernel);
      factor.add(A);
      const Eigen::MatrixXd R = factor.r();
      EXPECT_TRUE(R.isUpperTriangular());
      EXPECT_LT((R.transpose() * R - A.transpose() * A).norm(),
                kTolerance * (A.transpose() * A).norm())
          << "kernel " << static_cast<int>(kernel) << ", " << cols << " columns";
    }
  }
}

TEST(TallQr, KernelsAgree) {
  if (!TallQr::avx2Available()) GTEST_SKIP() << "this CPU has no AVX2 and FMA";
  // Graded columns (condition number ~1e6): the kernels differ only in rounding.
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(5000, 30);
  for (Eigen::Index c = 0; c < A.cols(); ++c) A.col(c) *= std::pow(10.0, -6.0 * c / 29.0);
  TallQr portable(30, 1024, TallQr::Kernel::kPortable), avx2(30, 1024, TallQr::Kernel::kAvx2);
  portable.add(A);
  avx2.add(A);
  const Eigen::MatrixXd Rp = portable.r(), Ra = avx2.r();
  // R is unique up to the signs of its rows; both kernels choose them the same way.
  EXPECT_LT((Rp - Ra).norm(), kTolerance * Rp.norm());
  EXPECT_LT((Rp.diagonal() - Ra.diagonal()).cwiseQuotient(Rp.diagonal()).cwiseAbs().maxCoeff(),
            1e-9);  // column 29 is 1e-6 of column 0: its pivot keeps ~1e-10 relative accuracy
}

TEST(TallQr, ZeroColumnsStayExactlyZero) {
  // An unexcited column must read as exactly 0, not as rounding noise: the excitation test
  // and the condition numbers depend on it. The AVX2 kernel takes columns in pairs: (0, 1) has
  // a zero first column, (4, 5) a zero second one, (6, 7) two, and 13 is the last, unpaired.
  const std::vector<Eigen::Index> zeros = {0, 5, 6, 7, 13};
  for (TallQr::Kernel kernel : kernels()) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Random(3000, 14);
    for (Eigen::Index c : zeros) A.col(c).setZero();
    TallQr factor(14, 1024, kernel);
    factor.add(A);
    const Eigen::MatrixXd R = factor.r();
    for (Eigen::Index c : zeros) {
      EXPECT_EQ(R.col(c).cwiseAbs().maxCoeff(), 0.0) << "column " << c;
      EXPECT_EQ(R.row(c).cwiseAbs().maxCoeff(), 0.0) << "row " << c;
    }
    EXPECT_LT((R.transpose() * R - A.transpose() * A).norm(),
              kTolerance * (A.transpose() * A).norm());
  }
}

TEST(TallQr, SameBitsForAnyHandingOver) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(2100, 9);
  const TallQr::RowMajorMatrix rows = A;
  for (TallQr::Kernel kernel : kernels()) {
    TallQr whole(9, 512, kernel), one_by_one(9, 512, kernel), chunks(9, 512, kernel);
    whole.add(A);
    for (Eigen::Index r = 0; r < A.rows(); ++r) one_by_one.addRow(A.row(r));
    for (Eigen::Index first = 0; first < A.rows(); first += 333)
      chunks.addRowMajor(rows.middleRows(first, std::min<Eigen::Index>(333, A.rows() - first)));
    // Written in place: up to room() rows at a time, 100 or fewer, committed as they come.
    TallQr in_place(9, 512, kernel);
    for (Eigen::Index first = 0; first < A.rows();) {
      const Eigen::Index k = std::min({in_place.room(), Eigen::Index{100}, A.rows() - first});
      for (Eigen::Index r = 0; r < k; ++r)
        for (Eigen::Index c = 0; c < 9; ++c)
          in_place.freeRows()[r * in_place.rowStride() + c] = A(first + r, c);
      in_place.commitRows(k);
      first += k;
    }
    const Eigen::MatrixXd R = whole.r();
    EXPECT_EQ(R, one_by_one.r());
    EXPECT_EQ(R, chunks.r());
    EXPECT_EQ(R, in_place.r());
    EXPECT_EQ(in_place.rowsAdded(), A.rows());
  }
  TallQr small(3, 4);
  EXPECT_EQ(small.room(), 4);
  small.commitRows(0);  // nothing: allowed
  EXPECT_THROW(small.commitRows(5), InputError);
  EXPECT_THROW(small.commitRows(-1), InputError);
}

TEST(StackedTriangularFactor, IsTheFactorOfBothFactorsRows) {
  // Graded columns (condition ~1e6) and a zero column in both: R^T R = A^T A + B^T B to
  // round-off, and the zero column stays exactly zero.
  for (Eigen::Index n : {1, 2, 7, 40, 65}) {
    Eigen::MatrixXd X = Eigen::MatrixXd::Random(3 * n + 5, n),
                    Y = Eigen::MatrixXd::Random(n + 9, n);
    for (Eigen::Index c = 0; c < n; ++c) {
      const double scale = std::pow(10.0, -6.0 * c / std::max<Eigen::Index>(n - 1, 1));
      X.col(c) *= scale;
      Y.col(c) *= scale;
    }
    if (n > 2) X.col(1).setZero(), Y.col(1).setZero();
    TallQr x(n), y(n), both(n);
    x.add(X);
    y.add(Y);
    both.add(X);
    both.add(Y);
    const Eigen::MatrixXd A = x.r(), B = y.r(), R = stackedTriangularFactor(A, B);
    EXPECT_TRUE(R.isUpperTriangular(0.0)) << n;
    const Eigen::MatrixXd gram = X.transpose() * X + Y.transpose() * Y;
    EXPECT_LT((R.transpose() * R - gram).norm(), kTolerance * gram.norm()) << n;
    // The same triangle as the dense reduction of every row, up to the rows' signs; the pivots to
    // the accuracy the grading leaves (column n-1 is 1e-6 of column 0).
    const Eigen::MatrixXd dense = both.r();
    EXPECT_LT((R.diagonal().cwiseAbs() - dense.diagonal().cwiseAbs())
                  .cwiseQuotient(dense.diagonal().cwiseAbs().cwiseMax(1e-300))
                  .cwiseAbs()
                  .maxCoeff(),
              1e-8)
        << n;
    if (n > 2) {
      EXPECT_EQ(R.col(1).cwiseAbs().maxCoeff(), 0.0);
      EXPECT_EQ(R.row(1).cwiseAbs().maxCoeff(), 0.0);
    }
    EXPECT_EQ(R, stackedTriangularFactor(A, B));  // the same bits again
  }
  // A factor with nothing to add (B zero) is A itself.
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(6, 6).triangularView<Eigen::Upper>();
  EXPECT_EQ(stackedTriangularFactor(A, Eigen::MatrixXd::Zero(6, 6)), A);
  EXPECT_THROW(stackedTriangularFactor(A, Eigen::MatrixXd::Zero(5, 5)), InputError);
  EXPECT_THROW(stackedTriangularFactor(Eigen::MatrixXd::Zero(6, 5), A), InputError);
}

}  // namespace
}  // namespace dynid
