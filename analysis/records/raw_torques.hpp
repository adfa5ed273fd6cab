// validate_raw.csv (dynid prepare --keep-raw-torque, written by reports/prepare_report): the
// held-out part's raw torques at the log's own stamps, read back by identify and predict.
#pragma once

#include <string>

#include <Eigen/Core>

namespace dynid {

/// The held-out part's raw torques at the log's own stamps (prepare --keep-raw-torque's
/// validate_raw.csv: t, tau1..taun; time on the datasets' axis).
struct RawTorques {
  std::string file;
  Eigen::VectorXd time;
  Eigen::MatrixXd tau;  // n x samples [N m]
};
/// Reads validate_raw.csv; ParseError naming the file, line and column for a header that is not
/// t,tau1..taun with n the robot's joints, a value that is not finite, or times that decrease.
RawTorques readRawTorques(const std::string& path, int num_joints);

}  // namespace dynid
