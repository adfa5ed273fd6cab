// Gaz et al.'s real Panda log (../shared/data/panda_gaz2019/) as a dynid Trajectory, for tests
// that identify the real robot before dynid has its own log import (`dynid prepare`).
#pragma once

#include <string>

#include "core/trajectory.hpp"

namespace dynid::test {

/// The log's directory beside the repository (DYNID_SOURCE_DIR/../shared/data/panda_gaz2019/),
/// or "" when it is not there.
std::string pandaLogDirectory();

/// Every `stride`-th sample of the log, at least `half_window` s from either end, with q, dq, ddq
/// and tau from a cubic fitted by least squares, per joint, to the raw positions (and a line to
/// the torques) within +-half_window s of the sample on the log's real, irregular time stamps.
/// Throws std::runtime_error when a file is missing or short.
Trajectory pandaLogTrajectory(const std::string& directory, int stride, double half_window);

}  // namespace dynid::test
