// Simulated payload logs for the payload tests (analysis and CLI): a tool body, an arm carrying
// it, a rich motion and its torques written as a dataset CSV.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"
#include "core/trajectory.hpp"

namespace dynid::test {

/// A 1.2 kg tool, centre of mass (0.03, -0.02, 0.08) m, principal moments 4, 6, 3 g m^2 about
/// axes turned by KUKA angles (0.3, -0.2, 0.4) rad: standard parameters in its own frame.
Eigen::Matrix<double, 10, 1> toolBody();
/// The PUMA's flange as the tests use it: 0.05 m along link 6's z, turned 45 degrees about it.
Pose<double> pumaFlange();
/// The arm carrying `body` (given in `tool`, a frame of link `link`).
Model withPayload(const Model& arm, int link, const Pose<double>& tool,
                  const Eigen::Matrix<double, 10, 1>& body);
/// Three harmonics per joint about 0, sampled at `rate` for `seconds`; `still` joints at 0.3 rad.
Trajectory payloadMotion(const Model& model, double seconds, double rate,
                         const std::vector<int>& still = {});
/// The motion with `model`'s torques, each joint's divided by gain[j] (current sensing with
/// wrong constants; empty: 1) plus white noise of `noise` [N m], written to tempPath(name).
std::string payloadLog(const Model& model, Trajectory t, const std::string& name,
                       double noise = 0.0, std::uint64_t seed = 1, Eigen::VectorXd gain = {});

}  // namespace dynid::test
