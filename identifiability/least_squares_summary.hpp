// A least-squares summary of samples: what a fit of the base parameters needs from them, in memory
// independent of their number, and mergeable exactly. Per batch of consecutive samples and per
// joint j, the triangular factor R_bj of [W1_j(:, support_j) | tau_j] (the rows a fit takes:
// FitRows applied; support_j the base columns that can act on joint j, as LeastSquaresStream keeps
// them).
//
// Every least-squares quantity follows from the batches' factors by orthogonal invariance:
//   the estimate (OLS, WLS, pc): the factor of every batch's rows stacked, the same as the factor
//     of every sample's rows (LeastSquaresStream::addFactors), so that summaries of several logs,
//     merged in any order, give the concatenated logs' estimate to round-off;
//   the robust covariance (identifiability/uncertainty/score_covariance.hpp, CR2) at any beta:
//     batch b's normal matrix H_b = sum_j l_j R_bj^T R_bj and score s_b = sum_j l_j R_bj^T R_bj
//     [-beta; 1] (l_j joint j's weight, columns scattered into the b base columns), exact for every
//     beta because the score is linear in it.
// A batch of the summary is a batch of the covariance: a summary of one stream keeps between
// kSummaryBatches and 2 kSummaryBatches batches (their length doubles, neighbours joined, as the
// samples come); merged summaries keep their batches (a batch never spans two logs) up to
// kMaxSummaryBatches, joining neighbours beyond. The batches are long against the residuals'
// correlation on any log of more than a few thousand samples (a 60 s log at 1 kHz: 1024 samples a
// batch), which the covariance policy asks of them; identify on the samples themselves chooses
// its batch length from the residuals (a few tens of samples), so the two covariances agree in
// expectation, not bit for bit.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/data.hpp"
#include "core/model.hpp"
#include "core/parallel.hpp"
#include "core/trajectory.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "identifiability/rows/fit_rows.hpp"
#include "identifiability/uncertainty/score_covariance.hpp"

namespace dynid {

/// A summary of one stream keeps at least this many batches once it has this many batches'
/// worth of samples (fewer for a short log: one per kFirstSummaryBatch samples).
inline constexpr int kSummaryBatches = 32;
/// Samples in a batch before any doubling.
inline constexpr long long kFirstSummaryBatch = 256;
/// Merged summaries keep at most this many batches (memory per summary bounded whatever the
/// number of logs: 256 batches of sum_j (s_j + 1)(s_j + 2) / 2 doubles).
inline constexpr int kMaxSummaryBatches = 256;

class LeastSquaresSummary {
 public:
  struct Batch {
    long long samples = 0;
    std::vector<Eigen::MatrixXd> factors;  // per joint: upper triangular, support_j + 1 square
  };

  LeastSquaresSummary() = default;
  /// An empty summary for the base parameters `base` of `model` (the stream's joint supports).
  LeastSquaresSummary(const BaseParameters& base, const Model& model);
  /// A summary from its parts (a document read back). Throws InputError when the parts disagree:
  /// the supports' columns out of range or not increasing, a factor of the wrong size or not upper
  /// triangular or not finite, totals of the wrong size, batches' samples that do not add up.
  LeastSquaresSummary(int num_base, std::vector<std::vector<int>> support,
                      std::vector<Batch> batches, Eigen::VectorXd fitted_rows,
                      Eigen::VectorXd tau_squared, double max_abs_tau);

  /// Adds the batches of `other`, a summary of the same base parameters and supports (InputError
  /// otherwise), after this one's; beyond kMaxSummaryBatches neighbours are joined. `other` may be
  /// this summary (its rows then counted twice).
  void merge(const LeastSquaresSummary& other);

  /// Joins neighbouring batches (0 and 1, 2 and 3, ...) while there are more than `most` (>= 1;
  /// InputError otherwise): a summary that will be merged with others can have the joins a merge
  /// would make beyond kMaxSummaryBatches made beforehand (a Dask task's, in parallel, instead of
  /// at the top of the merge tree).
  void joinBatchesBeyond(int most);

  /// Adds every row of the summary to `stream` (LeastSquaresStream::addFactors), of the same base
  /// parameters and supports (InputError otherwise).
  void addTo(LeastSquaresStream& stream) const;

  /// The covariance's batches at `beta` with the joints weighted by `weights` (n entries; ols, pc:
  /// ones; wls: 1 / sigma_j^2): each batch's score and (full, symmetric) normal matrix.
  std::vector<ScoreBatch> scoreBatches(const Eigen::VectorXd& weights,
                                       const Eigen::VectorXd& beta) const;

  int numJoints() const { return static_cast<int>(support_.size()); }
  int numBase() const { return b_; }
  long long numSamples() const { return samples_; }
  /// Per joint, the rows fitted (numSamples() less the rows FitRows left out).
  const Eigen::VectorXd& fittedRows() const { return fitted_rows_; }
  /// Per joint, the sum of the fitted rows' squared torques.
  const Eigen::VectorXd& tauSquared() const { return tau_squared_; }
  double maxAbsTau() const { return max_abs_tau_; }
  const std::vector<std::vector<int>>& support() const { return support_; }
  const std::vector<Batch>& batches() const { return batches_; }
  /// Doubles held (every batch's factors, their upper triangles): the summary's size.
  long long numValues() const;

 private:
  friend class SummaryBuilder;

  int b_ = 0;
  std::vector<std::vector<int>> support_;
  std::vector<Batch> batches_;
  long long samples_ = 0;
  Eigen::VectorXd fitted_rows_, tau_squared_;
  double max_abs_tau_ = 0.0;
};

/// Builds the summary of one stream of samples, chunk by chunk: the regressor rows of a chunk on
/// the pool's threads, each joint's rows folded into its batches in order (the same bits for any
/// thread count and any division into chunks).
class SummaryBuilder {
 public:
  SummaryBuilder(const BaseParameters& base, const Model& model);
  SummaryBuilder(SummaryBuilder&&) noexcept;
  ~SummaryBuilder();

  /// Adds every sample of `data` with `model`'s joint torque regressor (the model the builder was
  /// made for), the rows as `rows` takes them (its sample indices counted from this builder's
  /// first sample; null: every row). Throws InputError when the joint counts differ or a value is
  /// not finite (nothing added then).
  void addTrajectory(const Model& model, const Trajectory& data, ThreadPool* pool = nullptr,
                     const FitRows* rows = nullptr);
  long long numSamples() const { return summary_.samples_ + open_samples_; }
  /// The summary of every sample so far (the builder is not to be used after).
  LeastSquaresSummary finish();

 private:
  /// Closes the open batch into the summary's batches; doubles the batch length when there are
  /// 2 kSummaryBatches.
  void closeBatch();

  const BaseParameters& base_;
  LeastSquaresSummary summary_;
  std::vector<std::vector<Eigen::Index>> gather_;  // per joint: offsets into Y's storage
  struct Open;
  std::unique_ptr<Open> open_;  // the open batch's factors (TallQr, internal)
  long long open_samples_ = 0;
  long long batch_length_ = kFirstSummaryBatch;
  std::vector<std::unique_ptr<Data>> workspaces_;
  std::vector<Eigen::MatrixXd> adjusted_;  // per thread: a sample's regressor as the fit takes it
  // A chunk's rows per joint (row-major) and torques, kept between calls.
  std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> buffers_;
  Eigen::MatrixXd taus_;
};

}  // namespace dynid
