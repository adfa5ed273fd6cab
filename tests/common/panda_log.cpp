#include "tests/common/panda_log.hpp"

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <Eigen/Cholesky>

namespace dynid::test {

namespace {

std::vector<double> readColumn(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<double> out;
  for (double x = 0.0; in >> x;) out.push_back(x);
  return out;
}

}  // namespace

std::string pandaLogDirectory() {
  const std::string dir = std::string(DYNID_SOURCE_DIR) + "/../shared/data/panda_gaz2019/";
  return std::filesystem::exists(dir + "exciting_traj_torques.txt") ? dir : "";
}

Trajectory pandaLogTrajectory(const std::string& directory, int stride, double half_window) {
  constexpr int n = 7;
  const std::vector<double> time = readColumn(directory + "exciting_traj_time.txt");
  const std::vector<double> q = readColumn(directory + "exciting_traj_positions.txt");
  const std::vector<double> tau = readColumn(directory + "exciting_traj_torques.txt");
  const auto samples = static_cast<int>(time.size());
  if (samples < 100 || q.size() != time.size() * n || tau.size() != time.size() * n)
    throw std::runtime_error("the Panda log in " + directory + " is short or inconsistent");
  std::vector<int> picked;
  for (int k = 0; k < samples; k += stride)
    if (time[k] - time.front() >= half_window && time.back() - time[k] >= half_window)
      picked.push_back(k);
  Trajectory out;
  out.resize(n, static_cast<int>(picked.size()));
  int lo = 0, hi = 0;
  for (std::size_t s = 0; s < picked.size(); ++s) {
    const int k = picked[s];
    while (time[lo] < time[k] - half_window) ++lo;
    while (hi + 1 < samples && time[hi + 1] <= time[k] + half_window) ++hi;
    // Design in the scaled time u = (t - t_k) / h, so the normal equations stay well conditioned.
    const int m = hi - lo + 1;
    Eigen::MatrixXd A(m, 4);
    Eigen::MatrixXd Q(m, n), T(m, n);
    for (int r = 0; r < m; ++r) {
      const double u = (time[lo + r] - time[k]) / half_window;
      A.row(r) << 1.0, u, u * u, u * u * u;
      for (int j = 0; j < n; ++j) Q(r, j) = q[(lo + r) * n + j], T(r, j) = tau[(lo + r) * n + j];
    }
    const Eigen::MatrixXd cq = (A.transpose() * A).ldlt().solve(A.transpose() * Q);
    const Eigen::MatrixXd A2 = A.leftCols(2);
    const Eigen::MatrixXd ct = (A2.transpose() * A2).ldlt().solve(A2.transpose() * T);
    out.time[static_cast<Eigen::Index>(s)] = time[k];
    out.q.col(static_cast<Eigen::Index>(s)) = cq.row(0).transpose();
    out.dq.col(static_cast<Eigen::Index>(s)) = cq.row(1).transpose() / half_window;
    out.ddq.col(static_cast<Eigen::Index>(s)) =
        2.0 * cq.row(2).transpose() / (half_window * half_window);
    out.tau.col(static_cast<Eigen::Index>(s)) = ct.row(0).transpose();
  }
  return out;
}

}  // namespace dynid::test
