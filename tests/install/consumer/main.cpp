#include <cmath>
#include <cstdio>

#include <dynid/core/rnea.hpp>
#include <dynid/data/puma560.hpp>
#include <dynid/reports/demo_report.hpp>

int main() {
  const dynid::Model model = dynid::makePuma560();
  dynid::Data data(model);
  const Eigen::VectorXd q = dynid::puma560Pose("qn"), zero = Eigen::VectorXd::Zero(6);
  const double tau2 = dynid::rnea(model, data, q, zero, zero)[1];
  std::printf("gravity torque on joint 2 at qn: %.4f N m\n", tau2);
  // The report modules link too (an empty table is just its header).
  if (dynid::demoTable(dynid::DemoResult{}).find("method") != 0) return 1;
  return std::abs(tau2 - 31.6399) < 1e-4 ? 0 : 1;
}
