#include "identifiability/excitation.hpp"

#include <cmath>
#include <limits>

#include "core/errors.hpp"
#include "core/regressor.hpp"
#include "identifiability/tall_qr.hpp"

namespace dynid {

MotionScore scoreMotion(const Model& model, const BaseParameters& base, const Trajectory& motion,
                        double torque_noise) {
  const int n = model.numJoints(), samples = motion.numSamples(), b = base.numBase();
  if (motion.numJoints() != n)
    throw InputError("the motion has " + std::to_string(motion.numJoints()) + " joints, model '" +
                     model.name + "' has " + std::to_string(n));
  if (samples < 1) throw InputError("the motion has no samples");
  if (!(torque_noise > 0.0) || !std::isfinite(torque_noise))
    throw InputError("the torque noise must be > 0 and finite");
  if (base.numStandard() != model.parameterLayout().size())
    throw InputError("the base parameters are for another parameter layout");
  if (!motion.q.allFinite() || !motion.dq.allFinite() || !motion.ddq.allFinite())
    throw InputError("the motion has a value that is not finite");

  Data data(model);
  TallQr factor(b);
  Eigen::MatrixXd rows(n, b);
  for (int k = 0; k < samples; ++k) {
    const Eigen::MatrixXd& Y =
        jointTorqueRegressor(model, data, motion.q.col(k), motion.dq.col(k), motion.ddq.col(k));
    for (int j = 0; j < b; ++j) rows.col(j) = Y.col(base.independent[j]);
    factor.add(rows);
  }
  const Eigen::MatrixXd r = factor.r();  // R^T R = W1^T W1

  MotionScore out;
  out.samples = samples;
  out.condition = conditionNumber(r);
  // QR keeps column norms: those of W1 are those of R.
  const Eigen::VectorXd norms = r.colwise().norm().transpose();
  out.condition_unit = norms.minCoeff() > 0.0
                           ? conditionNumber(r * norms.cwiseInverse().asDiagonal())
                           : std::numeric_limits<double>::infinity();
  const double rows_total = static_cast<double>(samples) * n;
  out.log_det = 0.0;
  for (int j = 0; j < b; ++j) out.log_det += 2.0 * std::log(std::abs(r(j, j)));
  out.log_det -= b * std::log(rows_total);

  // diag((R^T R)^-1) = squared row norms of R^-1.
  out.std_dev.setConstant(b, std::numeric_limits<double>::infinity());
  if (std::isfinite(out.condition)) {
    const Eigen::MatrixXd r_inverse =
        r.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(b, b));
    out.std_dev = torque_noise * r_inverse.rowwise().norm();
  }
  const Eigen::VectorXd beta = base.project(model.standardParameters());
  out.relative_std = 100.0 * out.std_dev.cwiseQuotient(baseParameterScale(beta));
  out.relative_rms = b > 0 ? out.relative_std.norm() / (100.0 * std::sqrt(b)) : 0.0;
  return out;
}

}  // namespace dynid
