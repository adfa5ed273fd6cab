// dynid dynamics: tau = RNEA(q, dq, ddq), M(q), ddq = ABA(q, dq, tau) at one state.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "data/json_number.hpp"
#include "reports/model_report.hpp"

namespace dynid::cli {

int runDynamics(const std::vector<std::string>& args) {
  po::options_description options("dynid dynamics");
  addRobotOptions(options);
  options.add_options()("q", po::value<std::string>(),
                        "joint positions, comma-separated [rad] (default all 0)")(
      "dq", po::value<std::string>(), "joint velocities [rad/s] (default all 0)")(
      "ddq", po::value<std::string>(), "joint accelerations [rad/s^2]: tau = RNEA(q, dq, ddq)")(
      "tau", po::value<std::string>(), "joint torques [N m]: ddq = ABA(q, dq, tau)")(
      "json", po::bool_switch(),
      "print {\"schema_version\", \"tau\", \"M\", \"ddq\", ...} as JSON");
  po::variables_map vm;
  const std::string usage =
      "dynid dynamics --robot R [--drives] [--q LIST] [--dq LIST] [--ddq LIST | --tau LIST] "
      "[--json]";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  if (vm.count("ddq") && vm.count("tau"))
    throw UsageError("give --ddq or --tau, not both\nusage: " + usage);
  const Model model = loadRobotFromOptions(vm);
  const int n = model.numJoints();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  const DynamicsOutcome outcome = dynamicsAt(
      model, optionalJointVector(vm, "q", n, false).value_or(zero),
      optionalJointVector(vm, "dq", n, false).value_or(zero),
      optionalJointVector(vm, "ddq", n, false), optionalJointVector(vm, "tau", n, false));
  if (vm["json"].as<bool>())
    std::cout << jsonText(dynamicsJson(model, outcome)) << "\n";
  else
    std::cout << dynamicsText(model, outcome);
  return kExitOk;
}

}  // namespace dynid::cli
