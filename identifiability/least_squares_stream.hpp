// Least squares of the base parameters from samples streamed one at a time, in memory independent
// of their number: per joint j, the triangular factor R_j of [W1_j | tau_j] (W1_j the base
// regressor's rows of joint j, tau_j its torques), accumulated by TallQr (per lane of samples, the
// lanes' factors stacked at the end: a tall-skinny QR). Every quantity of a
// BaseEstimate follows from the n factors and per-joint sums, by orthogonal invariance:
//   OLS: R of [R_1; ...; R_n] (the QR of every row at once),
//   WLS: R of [R_1 / sigma_1; ...; R_n / sigma_n] with sigma_j from the OLS residuals,
//   residual of joint j at beta: |R_j [beta; -1]| (R_j's corner holds what W1_j cannot fit),
// so one pass over the data serves both methods, the excitation and the condition numbers.
//
// Given the model, joint j's factor holds only the base columns that can act on joint j (the
// parameters of the links it moves, its own drive terms): the regressor is block triangular, so
// R_j is smaller (half the work on a 6-joint chain) and the same after scattering its columns.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/data.hpp"
#include "core/model.hpp"
#include "core/parallel.hpp"
#include "core/trajectory.hpp"
#include "identifiability/base_estimate.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/rows/fit_rows.hpp"

namespace dynid {

class TallQr;  // identifiability/tall_qr.hpp, internal

/// Which base columns can act on each joint of `model` (base: its base parameters): per joint,
/// the base columns of the links it moves and its own drive terms (`support`, increasing), and
/// the standard columns that must be zero in its regressor row (`zeros`). InputError when `base`
/// is of another parameter count.
struct JointSupport {
  std::vector<std::vector<int>> support, zeros;
};
JointSupport jointSupport(const BaseParameters& base, const Model& model);
/// Per joint j, where its row's entries of `columns[j]` lie in an n x p regressor's column-major
/// storage (column * n + j), each column first mapped through `standard` when given (base column
/// -> standard index: BaseParameters::independent).
std::vector<std::vector<Eigen::Index>> regressorOffsets(
    const std::vector<std::vector<int>>& columns, int num_joints,
    const std::vector<int>* standard = nullptr);

class LeastSquaresStream {
 public:
  /// For the base parameters `base` of a model with `num_joints` joints: every factor holds every
  /// base column.
  LeastSquaresStream(const BaseParameters& base, int num_joints);
  /// For the base parameters of `model` (kept by reference, as `base`): joint j's factor holds the
  /// base columns of its subtree's links and its own drive terms. add() checks that the others are
  /// zero (Error otherwise: a regressor that does not have the chain's structure).
  LeastSquaresStream(const BaseParameters& base, const Model& model);
  // Out of line: TallQr is complete only in least_squares_stream.cpp.
  LeastSquaresStream(LeastSquaresStream&&) noexcept;
  ~LeastSquaresStream();

  /// Adds one sample: the joint torque regressor Y (n x p, the model's standard parameters) and
  /// the measured torques tau (n). Throws InputError on a size mismatch or a value that is not
  /// finite.
  void add(const Eigen::Ref<const Eigen::MatrixXd>& Y,
           const Eigen::Ref<const Eigen::VectorXd>& tau);

  /// Adds every sample of `data` (q, dq, ddq, tau) with the joint torque regressor of `model`, on
  /// the pool's threads (all of them; nullptr: this thread). The samples are dealt to a fixed
  /// number of lanes in fixed blocks by their index in the stream; a thread takes a lane, computes
  /// a block's regressors and folds them into the lane's own factors, so the result is the same
  /// bit for bit for any thread count and any division of the data into chunks, and the same as
  /// add() sample by sample. Throws InputError when the joint counts differ or a value is not
  /// finite (checkFiniteSample's message); nothing of `data` is added then. The chain's structure
  /// (add()'s Error) is a property of the model, so it is checked on each block's first sample;
  /// after that Error (a regressor bug, not bad data) the stream is not to be used further.
  ///
  /// With `rows`, the samples are those of rows' training set from numSamples() on, and each
  /// sample's regressor and torques are as rows->apply makes them: a row left out adds nothing
  /// and is not counted in its joint's rows (fittedRows()).
  void addTrajectory(const Model& model, const Trajectory& data, ThreadPool* pool = nullptr,
                     const FitRows* rows = nullptr);

  /// Adds rows given by their factors (a LeastSquaresSummary's): per joint j, an upper
  /// triangular factor of the rows' [W1_j(:, support()[j]) | tau_j], `samples` samples whose
  /// fitted rows (per joint), sum of squared fitted torques (per joint) and largest |tau| are
  /// given. Throws InputError on a size mismatch or a value that is not finite.
  void addFactors(const std::vector<Eigen::MatrixXd>& joint_factors, long long samples,
                  const Eigen::VectorXd& fitted_rows, const Eigen::VectorXd& tau_squared,
                  double max_abs_tau);
  /// Per joint, the base columns its factor holds.
  const std::vector<std::vector<int>>& support() const { return support_; }

  int numSamples() const { return samples_; }
  /// Per joint, the rows added (numSamples() each, less those FitRows left out).
  Eigen::VectorXd fittedRows() const;
  int numJoints() const { return n_; }

  /// The estimate from every sample so far, as estimateBaseParameters (more samples may follow;
  /// the next estimate takes them all): throws NumericalError when
  /// the samples do not excite every base parameter, InputError when there are fewer torque rows
  /// than base parameters.
  BaseEstimate estimate(LeastSquaresMethod method);

  /// The triangular factor of the column-scaled base regressor (unit column norms; an unexcited
  /// column stays 0) and the column norms: the excitation (|R_jj|) and the condition numbers.
  struct Factor {
    Eigen::MatrixXd r_scaled;  // b x b upper triangular
    Eigen::VectorXd norms;     // column norms of W1 (0: never excited)
  };
  Factor factor();

  /// The triangular factor [R c; 0 rho] ((b + 1) x (b + 1)) of [W1 | tau] over every sample so
  /// far: for any beta, |W1 beta - tau|^2 = |R beta - c|^2 + rho^2, and |tau|^2 is the squared
  /// norm of its last column.
  Eigen::MatrixXd augmentedFactor();
  /// Per joint j, the sum over every sample so far of (W1_j beta - tau_j)^2 (b entries in beta).
  Eigen::VectorXd residualSquares(const Eigen::VectorXd& beta);

 private:
  /// The stacked per-joint factors, joint j's rows times weight[j], reduced to one (b+1) factor.
  Eigen::MatrixXd combined(const Eigen::VectorXd& weight);

  void addTau(const Eigen::Ref<const Eigen::VectorXd>& tau);
  /// addTau for each sample of `data` (the stream's samples from `first`), a row `rows` leaves
  /// out as 0.
  void addTaus(const Trajectory& data, long long first, const FitRows* rows);
  /// gather_ and zero_offsets_ from support_ and zeros_.
  void makeGather();
  /// addTrajectory's InputErrors: joint counts and the parameter layout.
  void checkSizes(const Model& model, const Trajectory& data) const;
  /// Joint j's factor [W1_j(:, support_j) | tau_j] of every sample so far: the lanes' stacked.
  const Eigen::MatrixXd& jointFactor(int j);
  /// The same scattered into b + 1 columns.
  Eigen::MatrixXd scattered(int j);

  const BaseParameters& base_;
  int n_, b_;
  int samples_ = 0;
  std::vector<std::vector<int>> support_;  // per joint: the base columns its rows may hold
  std::vector<std::vector<int>> zeros_;    // per joint: the standard columns that must be 0
  // The same as offsets into the n x p regressor's column-major storage.
  std::vector<std::vector<Eigen::Index>> gather_, zero_offsets_;
  // Per lane (a fixed dealing of the samples in blocks, least_squares_stream.cpp) and joint, the
  // factor of [W1_j(:, support_j) | tau_j] of the lane's samples.
  std::vector<std::vector<TallQr>> lanes_;
  std::vector<Eigen::MatrixXd> joint_factors_;  // jointFactor's, for factored_samples_ samples
  // Rows added as factors (addFactors): per joint, their factor (empty before any), and the rows
  // among their samples that were not fitted.
  std::vector<Eigen::MatrixXd> given_;
  Eigen::VectorXd given_left_out_;
  long long factored_samples_ = -1;
  Eigen::VectorXd tau_squared_;  // per joint sum of tau^2
  // Per lane and joint, the rows FitRows left out (each lane's own: no two threads share one).
  std::vector<std::vector<long long>> left_out_;
  double max_abs_tau_ = 0.0;
  Eigen::RowVectorXd row_;
  std::vector<std::unique_ptr<Data>> workspaces_;  // addTrajectory's, one per thread
};

/// stream.addTrajectory(model, data, pool).
void addTrajectory(LeastSquaresStream& stream, const Model& model, const Trajectory& data,
                   ThreadPool* pool = nullptr);

}  // namespace dynid
