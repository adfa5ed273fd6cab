#include "analysis/logs/effort_scale.hpp"

#include <cmath>
#include <utility>

#include "core/errors.hpp"

namespace dynid {

Eigen::VectorXd effortScale(const Eigen::VectorXd& torque_constants,
                            const Eigen::VectorXd& gear_ratios, int num_joints,
                            const std::string& source) {
  if (torque_constants.size() == 0) {
    if (gear_ratios.size() > 0)
      throw InputError("`gear_ratios` applies to motor currents: give `torque_constants` too");
    return {};
  }
  for (const auto& [v, what] : {std::pair{&torque_constants, "`torque_constants`"},
                                std::pair{&gear_ratios, "`gear_ratios`"}}) {
    if (v->size() == 0) continue;
    if (v->size() != num_joints)
      throw InputError(std::string(what) + " has " + std::to_string(v->size()) + " values; " +
                       source + " has " + std::to_string(num_joints) +
                       " joints: give one per joint");
    for (Eigen::Index j = 0; j < num_joints; ++j)
      if (!std::isfinite((*v)[j]) || (*v)[j] == 0.0)
        throw InputError(std::string(what) + ": the value of joint " + std::to_string(j + 1) +
                         " must be finite and non-zero");
  }
  // Each product as prepare has always formed it: constant times (ratio, or 1).
  Eigen::VectorXd scale(num_joints);
  for (Eigen::Index j = 0; j < num_joints; ++j)
    scale[j] = torque_constants[j] * (gear_ratios.size() > 0 ? gear_ratios[j] : 1.0);
  return scale;
}

}  // namespace dynid
