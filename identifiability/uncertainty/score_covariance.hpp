// The one covariance policy of dynid's estimators: heteroscedasticity and autocorrelation
// consistent ("hac") over batches of consecutive samples, so that residuals correlated over time
// (filtered logs, model error) widen the intervals instead of shrinking them.
//
// For a (weighted) least-squares fit A x = y with residuals e (rows k n + j: n joints, sample k),
// sample k's rows are A_k and its score s_k = A_k^T e_k. Over batches b of consecutive samples,
// with H_b = sum_{k in b} A_k^T A_k, s_b = sum_{k in b} s_k and H = sum_b H_b,
//   Cov(x) = sum_b H^-1 (I - H_b H^-1)^-1/2 s_b s_b^T (I - H^-1 H_b)^-1/2 H^-1,
// the bias-reduced cluster-robust estimator ("CR2", Bell and McCaffrey 2002): its factor is
// A_b^T (I - P_bb)^-1/2 e_b moved into parameter space (A_b^T f(A_b H^-1 A_b^T) = f(H_b H^-1)
// A_b^T), P_bb the batch's block of the hat matrix, and makes it unbiased for independent residuals
// of any variance. Without the factor it is the batch-means sandwich H^-1 (sum_b s_b s_b^T) H^-1,
// which estimates the scores' long-run covariance when the residuals are correlated over less than
// a batch, but is biased low by each batch's leverage: on a smooth excitation a parameter is seen
// mostly in a few batches, and its score there is what the fit absorbed. With the factor (I - G)^-1
// instead of its square root it is the jackknife over batches ("CR3"), biased high by as much.
// Measured (tests/studies/audit_test.cpp, tests/cli/command_identify_test.cpp): on filtered PUMA
// sessions batch means covered 91 % with 95 % intervals, less as the batches grew; on a 4 s log
// with white noise the jackknife gave some standard deviations 1.9 times the white ones.
//
// The batch length: four times the first lag L, among 1, 2, 4, ..., 2048, at which the joints'
// mean autocorrelation of e falls below 0.05 (1 when lag 1 is already below; batch means
// underestimate the long-run variance by about sum_k 2 k rho_k / (B sum_k rho_k), 7 % at B = 4 L
// for AR(1) residuals), at most a thirtieth of the samples (at least 30 batches), and at least the
// storage length: the samples are stored in at most kMaxScoreBatches batches (each its H_b and
// s_b, memory independent of the number of samples), longer batches made by joining them.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

namespace dynid {

/// Batches stored: the storage length is the least power of two that keeps the expected samples in
/// this many batches (so at least kMaxScoreBatches / 2 batches of a long log).
inline constexpr int kMaxScoreBatches = 256;
/// The longest lag whose autocorrelation is measured [samples].
inline constexpr int kMaxScoreLag = 2048;
/// The autocorrelation below which residuals `lag` samples apart count as independent.
inline constexpr double kScoreIndependence = 0.05;

/// One batch of consecutive samples: its rows' summed score s_b and normal matrix H_b (full,
/// symmetric).
struct ScoreBatch {
  Eigen::VectorXd score;
  Eigen::MatrixXd normal;
};
/// The covariance (CR2) over `batches`, whose normal matrices sum to `h` (d x d, symmetric). A
/// direction only one batch sees (leverage 1) has its weight capped at 1000. Throws NumericalError
/// when h is not positive definite.
Eigen::MatrixXd robustCovariance(const Eigen::MatrixXd& h, const std::vector<ScoreBatch>& batches);

class ScoreCovariance {
 public:
  /// For `num_unknowns` unknowns, `num_joints` rows per sample and about `expected_samples`
  /// samples (more may come; they are stored in more batches). `batch` > 0 fixes the batch length
  /// (any length, every batch stored); 0 chooses it. Throws InputError for sizes < 1 or a negative
  /// batch.
  ScoreCovariance(Eigen::Index num_unknowns, int num_joints, long long expected_samples,
                  int batch = 0);

  /// Adds the next sample: its rows A_k (num_joints x num_unknowns) and residuals e_k, both as the
  /// fit weighs them. Throws InputError on a size mismatch.
  void add(const Eigen::Ref<const Eigen::MatrixXd>& rows,
           const Eigen::Ref<const Eigen::VectorXd>& residual);

  /// Consecutive samples prepared apart (on any thread): their rows' scores summed, their normal
  /// matrix (lower triangle) and their residuals (num_joints x samples).
  struct Block {
    Eigen::VectorXd score;
    Eigen::MatrixXd normal;
    Eigen::MatrixXd residuals;
  };
  /// A block from its samples' rows stacked (rows k n .. k n + n - 1: sample k's) and residuals.
  static Block prepare(const Eigen::Ref<const Eigen::MatrixXd>& rows,
                       const Eigen::Ref<const Eigen::MatrixXd>& residuals);
  /// Adds the next samples as a block; it must not cross a stored batch's end (storageLength()).
  /// The same sums as add() sample by sample, to round-off. Throws InputError on a size mismatch or
  /// a block that crosses.
  void add(const Block& block);
  /// Samples per stored batch: blocks start and end within one.
  long long storageLength() const { return storage_; }

  long long samples() const { return samples_; }
  /// The batch length used (1 before any sample).
  int batch() const;
  /// The joints' mean autocorrelation of the residuals at lag 2^i (i = 0, 1, ...; lags of a
  /// thirtieth of the samples or more are not reported): what chose the batch.
  std::vector<double> autocorrelation() const;
  /// H = sum_k A_k^T A_k.
  Eigen::MatrixXd normal() const;
  /// sum_b s_b s_b^T over the batches of batch() samples, times rows / (rows - unknowns): the
  /// batch-means sandwich's middle (for a pseudo-inverse of a singular H; no leverage correction).
  Eigen::MatrixXd meat() const;
  /// robustCovariance over the batches of batch() samples.
  Eigen::MatrixXd covariance() const;

 private:
  using Batch = ScoreBatch;  // stored: the normal's lower triangle; joined: full
  /// The stored batches joined into batches of `length` samples.
  std::vector<Batch> joined(long long length) const;
  /// The autocorrelation sums of the next sample's residuals.
  void lag(const Eigen::Ref<const Eigen::VectorXd>& residual);

  Eigen::Index d_;
  int n_;
  long long storage_ = 1;  // samples per stored batch
  bool fixed_ = false;
  long long samples_ = 0;
  std::vector<Batch> stored_;  // the last one may be partial
  // The residuals' autocorrelation at lags 2^i: a ring of the last kMaxScoreLag residuals.
  Eigen::MatrixXd ring_;
  Eigen::VectorXd energy_;                       // per joint, sum of e^2
  static constexpr int kLags = 12;               // 1 .. 2048
  std::array<Eigen::VectorXd, kLags> lagged_{};  // per lag, per joint sum e_k e_{k-L}
};

}  // namespace dynid
