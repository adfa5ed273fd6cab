#include "analysis/records/raw_torques.hpp"

#include <vector>

#include "analysis/logs/raw_log.hpp"
#include "core/errors.hpp"

namespace dynid {

RawTorques readRawTorques(const std::string& path, int num_joints) {
  const RawTable header = readRawHeader(path);
  std::vector<std::string> want = {"t"};
  for (int j = 1; j <= num_joints; ++j) want.push_back("tau" + std::to_string(j));
  if (header.names != want)
    throw ParseError(path, header.first_data_line > 1 ? 1 : 0, "",
                     "not a raw torque file of " + std::to_string(num_joints) +
                         " joints (prepare's `keep_raw_torque` validate_raw.csv: header t,tau1.." +
                         "tau" + std::to_string(num_joints) + ")");
  std::vector<int> columns(want.size());
  for (std::size_t c = 0; c < columns.size(); ++c) columns[c] = static_cast<int>(c);
  const Eigen::MatrixXd values = readRawColumns(header, columns);
  RawTorques out;
  out.file = path;
  out.time = values.col(0);
  out.tau = values.rightCols(num_joints).transpose();
  for (Eigen::Index k = 1; k < out.time.size(); ++k)
    if (!(out.time[k] > out.time[k - 1]))
      throw ParseError(path, rawRowLine(header, k), "t", "times must increase");
  return out;
}

}  // namespace dynid
