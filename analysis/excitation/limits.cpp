#include "analysis/excitation/limits.hpp"

#include <algorithm>
#include <cmath>

#include "core/data.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/kinematics.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {

std::string jointName(const Model& model, int j) { return model.joint_names[j]; }

void checkJointVector(const Eigen::VectorXd& v, int n, const std::string& what) {
  if (v.size() != n)
    throw InputError(what + " has " + std::to_string(v.size()) + " entries, the model has " +
                     std::to_string(n) + " joints");
}

}  // namespace

void checkOffsets(const Model& model, const ExcitationLimits& limits,
                  const Eigen::VectorXd& offset) {
  checkJointVector(offset, model.numJoints(), "the offset");
  for (int j = 0; j < model.numJoints(); ++j)
    if (!(offset[j] > limits.q_min[j] && offset[j] < limits.q_max[j]))
      throw InputError("joint '" + model.joint_names[j] + "' at " + formatNumber(offset[j]) +
                       " is not inside its position range (" + formatNumber(limits.q_min[j]) +
                       ", " + formatNumber(limits.q_max[j]) + ")");
}

ExcitationLimits excitationLimits(const Model& model, const LimitOverrides& o) {
  const int n = model.numJoints();
  for (const auto* v : {&o.q_min, &o.q_max, &o.dq_max, &o.ddq_max, &o.tau_max})
    if (*v) checkJointVector(**v, n, "a limit");
  ExcitationLimits l;
  l.q_min.resize(n);
  l.q_max.resize(n);
  l.dq_max.resize(n);
  l.ddq_max.resize(n);
  l.tau_max.resize(n);
  std::vector<std::string> position, velocity, acceleration, torque;
  for (int j = 0; j < n; ++j) {
    const JointLimits& m = model.limits[j];
    const bool prismatic = model.joint_types()[j] == JointType::kPrismatic;
    const double range = prismatic ? kDefaultPrismaticRange : kDefaultRevoluteRange;
    l.q_min[j] = o.q_min ? (*o.q_min)[j] : m.lower;
    l.q_max[j] = o.q_max ? (*o.q_max)[j] : m.upper;
    if (!std::isfinite(l.q_min[j]) || !std::isfinite(l.q_max[j])) {
      if (!std::isfinite(l.q_min[j])) l.q_min[j] = -range;
      if (!std::isfinite(l.q_max[j])) l.q_max[j] = range;
      position.push_back(jointName(model, j));
    }
    l.dq_max[j] = o.dq_max ? (*o.dq_max)[j] : m.velocity;
    if (!std::isfinite(l.dq_max[j])) {
      l.dq_max[j] = kDefaultVelocityLimit;
      velocity.push_back(jointName(model, j));
    }
    l.ddq_max[j] = o.ddq_max ? (*o.ddq_max)[j] : m.acceleration;
    if (!std::isfinite(l.ddq_max[j])) {
      l.ddq_max[j] = kDefaultAccelerationLimit;
      acceleration.push_back(jointName(model, j));
    }
    l.tau_max[j] = o.tau_max ? (*o.tau_max)[j] : m.effort;
    if (!std::isfinite(l.tau_max[j])) torque.push_back(jointName(model, j));
    const std::string joint = "joint '" + jointName(model, j) + "': ";
    if (!(l.q_min[j] < l.q_max[j]))
      throw InputError(joint + "the position range [" + formatNumber(l.q_min[j]) + ", " +
                       formatNumber(l.q_max[j]) + "] is empty");
    if (!(l.dq_max[j] > 0.0))
      throw InputError(joint + "the velocity limit must be > 0, not " + formatNumber(l.dq_max[j]));
    if (!(l.ddq_max[j] > 0.0))
      throw InputError(joint + "the acceleration limit must be > 0, not " +
                       formatNumber(l.ddq_max[j]));
    if (!(l.tau_max[j] > 0.0))
      throw InputError(joint + "the torque limit must be > 0, not " + formatNumber(l.tau_max[j]));
  }
  // A torque limit on some joints only: the others get none (no constraint).
  if (!torque.empty() && static_cast<int>(torque.size()) < n)
    for (int j = 0; j < n; ++j)
      if (!std::isfinite(l.tau_max[j])) l.tau_max[j] = std::numeric_limits<double>::infinity();
  auto note = [&](const std::vector<std::string>& joints, const std::string& what,
                  const std::string& used) {
    if (joints.empty()) return;
    std::string list;
    for (const std::string& j : joints) list += (list.empty() ? "" : ", ") + j;
    l.notes.push_back("the model gives no " + what + " for " + list + ": " + used);
  };
  note(position, "position limits",
       "+-" + formatNumber(kDefaultRevoluteRange, 6) + " rad (+-" +
           formatNumber(kDefaultPrismaticRange) + " m prismatic) used");
  note(velocity, "velocity limit", formatNumber(kDefaultVelocityLimit) + " rad/s used");
  note(acceleration, "acceleration limit",
       formatNumber(kDefaultAccelerationLimit) + " rad/s^2 used");
  note(torque, "torque limit", "torques not limited");
  if (!(o.torque_margin > 0.0 && o.torque_margin <= 1.0))
    throw InputError("the torque margin must be in (0, 1], not " + formatNumber(o.torque_margin));
  if (!(o.base_radius >= 0.0) || !std::isfinite(o.base_radius))
    throw InputError("the base radius must be >= 0 and finite, not " + formatNumber(o.base_radius));
  if (o.floor && !std::isfinite(*o.floor)) throw InputError("the floor must be finite");
  l.torque_margin = o.torque_margin;
  l.floor = o.floor;
  l.base_radius = o.base_radius;
  return l;
}

LimitCheck checkLimits(const Model& model, const Trajectory& motion,
                       const ExcitationLimits& limits) {
  const int n = model.numJoints();
  LimitCheck c;
  c.rate = motion.numSamples() > 1
               ? (motion.numSamples() - 1) / (motion.time[motion.numSamples() - 1] - motion.time[0])
               : 0.0;
  c.q_low = motion.q.rowwise().minCoeff();
  c.q_high = motion.q.rowwise().maxCoeff();
  c.dq_peak = motion.dq.cwiseAbs().rowwise().maxCoeff();
  c.ddq_peak = motion.ddq.cwiseAbs().rowwise().maxCoeff();
  c.tau_peak = motion.tau.cwiseAbs().rowwise().maxCoeff();
  auto violation = [&](int j, const std::string& what, double value, double limit) {
    c.violations.push_back("joint '" + model.joint_names[j] + "': " + what + " " +
                           formatNumber(value) + " beyond " + formatNumber(limit));
  };
  for (int j = 0; j < n; ++j) {
    if (c.q_low[j] < limits.q_min[j]) violation(j, "position", c.q_low[j], limits.q_min[j]);
    if (c.q_high[j] > limits.q_max[j]) violation(j, "position", c.q_high[j], limits.q_max[j]);
    if (c.dq_peak[j] > limits.dq_max[j]) violation(j, "speed", c.dq_peak[j], limits.dq_max[j]);
    if (c.ddq_peak[j] > limits.ddq_max[j])
      violation(j, "acceleration", c.ddq_peak[j], limits.ddq_max[j]);
    const double tau_limit = limits.torque_margin * limits.tau_max[j];
    if (c.tau_peak[j] > tau_limit) violation(j, "torque", c.tau_peak[j], tau_limit);
  }
  if (limits.floor || limits.base_radius > 0.0) {
    Data data(model);
    c.lowest_origin = c.nearest_base = std::numeric_limits<double>::infinity();
    for (int k = 0; k < motion.numSamples(); ++k) {
      const auto& frames = forwardKinematics(model, data, motion.q.col(k));
      for (const auto& f : frames) c.lowest_origin = std::min(c.lowest_origin, f.translation.z());
      c.nearest_base = std::min(c.nearest_base, frames.back().translation.head<2>().norm());
    }
    if (limits.floor && c.lowest_origin < *limits.floor)
      c.violations.push_back("a link origin at z = " + formatNumber(c.lowest_origin) +
                             " m, below the floor at " + formatNumber(*limits.floor) + " m");
    if (c.nearest_base < limits.base_radius)
      c.violations.push_back("the last link's origin " + formatNumber(c.nearest_base) +
                             " m from the base axis, inside the radius " +
                             formatNumber(limits.base_radius) + " m");
  }
  return c;
}

}  // namespace dynid
