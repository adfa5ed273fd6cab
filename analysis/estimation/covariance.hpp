// The one covariance policy (identifiability/uncertainty/score_covariance.hpp) applied to the
// pipeline's least-squares estimates (ols, wls, pc and, through pc, combined): robust over
// batches of consecutive samples at the estimate, from a second pass over the training data (a
// stream keeps only its triangular factors, and the scores need the residuals at the final
// estimate), or from the rows of an observation held in memory.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"
#include "core/parallel.hpp"
#include "core/trajectory.hpp"
#include "identifiability/base_estimate.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares_summary.hpp"
#include "identifiability/observation.hpp"
#include "identifiability/physically_consistent.hpp"
#include "identifiability/rows/fit_rows.hpp"

namespace dynid {

enum class CovariancePolicy {
  kHac,    // robust over batches of samples (default): correlated residuals count
  kWhite,  // sigma^2 (W1^T W1)^-1: residuals taken as white (the literature's; one pass)
};
const char* covariancePolicyName(CovariancePolicy policy);  // "hac", "white"
/// Throws InputError for another name ("unknown covariance policy ...").
CovariancePolicy covariancePolicyFrom(const std::string& name);

/// What a covariance was computed with, for the documents and the reports.
struct CovarianceSummary {
  std::string policy = "white";  // "hac" or "white"
  int batch = 1;                 // samples per batch
  /// The median over the base parameters of the standard deviation over the white one: how much
  /// the residuals' correlation widens the intervals (1 for white).
  double inflation = 1.0;
  std::vector<double> autocorrelation;  // the residuals' at lags 1, 2, 4, ...
};

/// Replays the training data to `each`, chunk by chunk, in order.
using TrainingReplay = std::function<void(const std::function<void(const Trajectory&)>& each)>;

/// How the estimate weighs the rows: ols and pc equally, wls joint j's by 1 / sigma_j^2.
struct ScoreWeights {
  Eigen::VectorXd per_joint;  // lambda_j, the weight of joint j's squared residual
};
/// The weights of `estimate`: wls (weighted) its joint_sigma's, otherwise equal.
ScoreWeights scoreWeights(const BaseEstimate& estimate, bool weighted);

/// The policy's covariance of `estimate` at its beta, from the data `replay` gives (each sample's
/// base regressor row W1_k = Y(:, independent) of `model`, on the pool's threads; the result is
/// the same for any thread count). Replaces estimate.covariance, std_dev and
/// relative_std_dev_percent (and pc's covariance and std_dev when given) and returns the summary.
/// With `rows`, each sample's rows as the fit took them (rows->apply: a row left out adds
/// nothing). Throws InputError when the replay's samples differ in number from the estimate's.
CovarianceSummary applyHacCovariance(const Model& model, const BaseParameters& base,
                                     const TrainingReplay& replay, ThreadPool* pool,
                                     const ScoreWeights& weights, BaseEstimate& estimate,
                                     PhysicalEstimate* pc = nullptr, const FitRows* rows = nullptr);
/// The same from a summary's batches (identifiability/least_squares_summary.hpp): its batches are
/// the covariance's (their length the summary's, not chosen from the residuals, which a summary
/// does not hold: `autocorrelation` stays empty).
CovarianceSummary applyHacCovariance(const LeastSquaresSummary& summary,
                                     const ScoreWeights& weights, BaseEstimate& estimate,
                                     PhysicalEstimate* pc = nullptr);
/// The same from an observation's rows.
CovarianceSummary applyHacCovariance(const BaseParameters& base, const Observation& observation,
                                     const ScoreWeights& weights, BaseEstimate& estimate,
                                     PhysicalEstimate* pc = nullptr);

}  // namespace dynid
