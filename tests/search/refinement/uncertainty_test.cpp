// The uncertainty in base coordinates: the starts' Schur complement.
#include "search/refinement/uncertainty.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/errors.hpp"
#include "core/perturb.hpp"
#include "data/puma560.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/observation.hpp"
#include "tests/common/gradient_check.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {
Eigen::MatrixXd uniformMatrix(std::mt19937_64& rng, int rows, int cols) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd out(rows, cols);
  for (int c = 0; c < cols; ++c)
    for (int r = 0; r < rows; ++r) out(r, c) = u(rng);
  return out;
}

TEST(RefineUncertainty, EliminateStartsEqualsTheDenseSchurComplement) {
  // Five segments with beta (4 columns) and starts (3 columns each); segments 0, 1 and 3 chain
  // into the next one's start, segment 2 ends at a gap and segment 4 is the last.
  using Block = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int segments = 5, b = 4, w = 3, m = 6;
  std::mt19937_64 rng(7);
  std::vector<Block> jb(segments), js(segments), jn(segments);
  const bool chained[segments] = {true, true, false, true, false};
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m * segments, b + w * segments);
  for (int s = 0; s < segments; ++s) {
    jb[s] = uniformMatrix(rng, m, b);
    js[s] = uniformMatrix(rng, m, w);
    jn[s] = chained[s] ? Block(uniformMatrix(rng, m, w)) : Block(m, 0);
    J.block(m * s, 0, m, b) = jb[s];
    J.block(m * s, b + w * s, m, w) = js[s];
    if (chained[s]) J.block(m * s, b + w * (s + 1), m, w) = jn[s];
  }
  const Eigen::MatrixXd H = J.transpose() * J;
  const Eigen::MatrixXd Hss = H.bottomRightCorner(w * segments, w * segments);
  const Eigen::MatrixXd expected =
      H.topLeftCorner(b, b) -
      H.topRightCorner(b, w * segments) * Hss.ldlt().solve(H.bottomLeftCorner(w * segments, b));
  // Both are the same 4x4 matrix of O(10) entries from well-conditioned blocks: round-off only.
  EXPECT_LT((eliminateStarts(jb, js, jn) - expected).norm(), 1e-10 * expected.norm());
  // Measured starts (no start columns): the plain Gauss-Newton matrix.
  std::vector<Block> none(segments, Block(m, 0));
  Eigen::MatrixXd plain = Eigen::MatrixXd::Zero(b, b);
  for (const Block& j : jb) plain += j.transpose() * j;
  EXPECT_LT((eliminateStarts(jb, none, none) - plain).norm(), 1e-12 * plain.norm());
  // A start no residual sees (segment 0's: no segment chains into it) leaves H_ss singular: NaN,
  // not a number that looks valid.
  js[0].setZero();
  EXPECT_TRUE(eliminateStarts(jb, js, jn).array().isNaN().all());
}

}  // namespace
}  // namespace dynid
