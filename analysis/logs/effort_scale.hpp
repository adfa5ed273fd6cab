// The one conversion of raw efforts that are motor currents into joint torques, shared by dynid
// prepare (a log's currents) and dynid monitor (a recording's or stdin's):
//   tau_j = current_j * torque_constants_j * gear_ratios_j   [N m/A; no gear ratios: 1].
#pragma once

#include <string>

#include <Eigen/Core>

namespace dynid {

/// Per joint, what a raw effort is multiplied by to give the joint torque: torque constant times
/// gear ratio (torque_constants_j * gear_ratios_j; gear_ratios empty: 1), or empty when both are
/// empty (the efforts are torques). `source` names what has the `num_joints` joints in a count's
/// message ("the robot", "the log (tau.txt)"). Throws InputError naming the field
/// (`torque_constants`, `gear_ratios`) for gear ratios without torque constants, a count other
/// than num_joints, or a value that is zero or not finite.
Eigen::VectorXd effortScale(const Eigen::VectorXd& torque_constants,
                            const Eigen::VectorXd& gear_ratios, int num_joints,
                            const std::string& source);

}  // namespace dynid
