// dynid dynamics: tau = RNEA(q, dq, ddq), M(q), ddq = ABA(q, dq, tau) at one state.
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "core/aba.hpp"
#include "core/crba.hpp"
#include "core/rnea.hpp"

namespace dynid::cli {

namespace {
nlohmann::json toJson(const Eigen::VectorXd& v) { return std::vector<double>(v.begin(), v.end()); }
void printVector(const char* name, const char* unit, const Eigen::VectorXd& v) {
  std::printf("%-4s [%s]:", name, unit);
  for (double x : v) std::printf(" % .10g", x);
  std::printf("\n");
}
}  // namespace

int runDynamics(const std::vector<std::string>& args) {
  po::options_description options("dynid dynamics");
  addRobotOptions(options);
  options.add_options()("q", po::value<std::string>(),
                        "joint positions, comma-separated [rad] "
                        "(default all 0)")("dq", po::value<std::string>(),
                                           "joint velocities [rad/s] (default all 0)")(
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
  auto joint_vector = [&](const char* name) {
    return vm.count(name) ? parseJointVector(vm[name].as<std::string>(), name, n, false)
                          : Eigen::VectorXd::Zero(n).eval();
  };
  const Eigen::VectorXd q = joint_vector("q"), dq = joint_vector("dq");
  Data data(model);
  // With --tau: ddq = ABA(q, dq, tau), and tau is echoed; otherwise tau = RNEA(q, dq, ddq).
  Eigen::VectorXd ddq, tau;
  if (vm.count("tau")) {
    tau = joint_vector("tau");
    ddq = aba(model, data, q, dq, tau);
  } else {
    ddq = joint_vector("ddq");
    tau = rnea(model, data, q, dq, ddq);
  }
  const Eigen::MatrixXd M = crba(model, data, q);
  if (!ddq.allFinite() || !tau.allFinite() || !M.allFinite())
    throw NumericalError("the dynamics of '" + model.name +
                         "' are singular at this state: the mass matrix is not positive definite "
                         "(is a moving subtree massless?)");
  if (vm["json"].as<bool>()) {
    nlohmann::json m = nlohmann::json::array();
    for (int r = 0; r < n; ++r) m.push_back(toJson(M.row(r).transpose()));
    std::cout << nlohmann::json{{"schema_version", 1},
                                {"robot", model.name},
                                {"drives", model.drives_enabled},
                                {"q", toJson(q)},
                                {"dq", toJson(dq)},
                                {"tau", toJson(tau)},
                                {"M", m},
                                {"ddq", toJson(ddq)}}
                     .dump()
              << "\n";
    return kExitOk;
  }
  std::printf("robot %s (drives %s)\n", model.name.c_str(), model.drives_enabled ? "on" : "off");
  printVector("q", "rad", q);
  printVector("dq", "rad/s", dq);
  printVector("ddq", "rad/s^2", ddq);
  printVector("tau", "N m", tau);
  std::printf("M(q) [kg m^2]:\n");
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) std::printf(" % .6e", M(r, c));
    std::printf("\n");
  }
  return kExitOk;
}

}  // namespace dynid::cli
