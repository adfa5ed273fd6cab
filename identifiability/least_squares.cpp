#include "identifiability/least_squares.hpp"

#include <algorithm>
#include <limits>

#include "core/errors.hpp"
#include "identifiability/least_squares_stream.hpp"

namespace dynid {

Eigen::VectorXd jointRms(const Eigen::VectorXd& r, int n) {
  const Eigen::Index samples = r.size() / n;
  const Eigen::Map<const Eigen::MatrixXd> by_joint(r.data(), n, samples);
  return (by_joint.rowwise().squaredNorm() / std::max<double>(static_cast<double>(samples), 1.0))
      .cwiseSqrt();
}

BaseEstimate estimateBaseParameters(const BaseParameters& base, const Observation& observation,
                                    LeastSquaresMethod method) {
  const int n = observation.num_joints, b = base.numBase();
  const Eigen::MatrixXd& W = observation.W;
  if (W.cols() != base.numStandard())
    throw InputError("observation matrix has " + std::to_string(W.cols()) + " columns, expected " +
                     std::to_string(base.numStandard()));
  if (W.rows() < b)
    throw InputError("the data has " + std::to_string(W.rows()) + " torque rows, fewer than the " +
                     std::to_string(b) + " base parameters");
  // The one least-squares path: the observation's samples streamed as any dataset's are.
  LeastSquaresStream stream(base, n);
  for (int k = 0; k < observation.num_samples; ++k) {
    const Eigen::Index row = static_cast<Eigen::Index>(k) * n;
    stream.add(W.middleRows(row, n), observation.tau.segment(row, n));
  }
  return stream.estimate(method);
}

Validation validateBaseEstimate(const BaseParameters& base, const Eigen::VectorXd& beta,
                                const Observation& observation) {
  const int n = observation.num_joints;
  if (beta.size() != base.numBase())
    throw InputError("base estimate has " + std::to_string(beta.size()) + " entries, expected " +
                     std::to_string(base.numBase()));
  if (observation.W.cols() != base.numStandard())
    throw InputError("observation matrix has " + std::to_string(observation.W.cols()) +
                     " columns, expected " + std::to_string(base.numStandard()));
  // tau - W1 beta as tau - W theta1, theta1 = beta at the independent columns (no copy of W1).
  Eigen::VectorXd theta1 = Eigen::VectorXd::Zero(base.numStandard());
  for (int j = 0; j < base.numBase(); ++j) theta1[base.independent[j]] = beta[j];
  const Eigen::VectorXd residual = observation.tau - observation.W * theta1;
  Validation out;
  out.num_samples = observation.num_samples;
  out.torque_rms = jointRms(residual, n);
  const Eigen::VectorXd tau_rms = jointRms(observation.tau, n);
  out.relative_error = tau_rms.norm() > 0.0 ? out.torque_rms.norm() / tau_rms.norm()
                                            : std::numeric_limits<double>::infinity();
  out.normalised_rms.resize(n);
  for (int j = 0; j < n; ++j)
    out.normalised_rms[j] =
        tau_rms[j] > 0.0 ? out.torque_rms[j] / tau_rms[j] : std::numeric_limits<double>::infinity();
  return out;
}

}  // namespace dynid
