#include "identifiability/tall_qr.hpp"

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

}  // namespace
}  // namespace dynid
