#include "cli/common.hpp"

#include <cmath>
#include <cstdlib>
#include <iostream>

#include "data/robots.hpp"

namespace dynid::cli {

bool parseCommandLine(const std::vector<std::string>& args, const po::options_description& options,
                      const std::string& usage, po::variables_map& vm) {
  po::options_description all;
  all.add_options()("help,h", "show this help");
  all.add(options);
  try {
    // Long options only, so negative numbers ("--q -0.5,1") are values, not short options.
    const auto style = po::command_line_style::unix_style ^ po::command_line_style::allow_short;
    po::store(po::command_line_parser(args).options(all).style(style).run(), vm);
    if (vm.count("help")) {
      std::cout << "usage: " << usage << "\n\n" << all << "\n";
      return false;
    }
    po::notify(vm);
  } catch (const po::error& e) {
    throw UsageError(std::string(e.what()) + "\nusage: " + usage + " (--help for the options)");
  }
  return true;
}

std::vector<double> parseList(const std::string& text, const std::string& option) {
  std::vector<double> out;
  std::size_t start = 0;
  for (int entry = 1;; ++entry) {
    const std::size_t comma = text.find(',', start);
    const std::string field = text.substr(start, comma - start);
    char* end = nullptr;
    const double x = std::strtod(field.c_str(), &end);
    if (field.empty() || end != field.c_str() + field.size() || !std::isfinite(x))
      throw UsageError("--" + option + ": entry " + std::to_string(entry) + " '" + field +
                       "' is not a finite number");
    out.push_back(x);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

Eigen::VectorXd parseJointVector(const std::string& text, const std::string& option, int n,
                                 bool allow_broadcast) {
  const std::vector<double> list = parseList(text, option);
  if (allow_broadcast && list.size() == 1) return Eigen::VectorXd::Constant(n, list[0]);
  if (static_cast<int>(list.size()) != n)
    throw UsageError("--" + option + " has " + std::to_string(list.size()) +
                     " entries, the robot has " + std::to_string(n) + " joints" +
                     (allow_broadcast ? " (or give one value for all)" : ""));
  return Eigen::Map<const Eigen::VectorXd>(list.data(), n);
}

void addRobotOptions(po::options_description& options) {
  options.add_options()("robot", po::value<std::string>()->required(),
                        "puma560, puma560-consistent, a .urdf file or a dynid .json model")(
      "drives", po::bool_switch(), "enable rotor inertia and joint friction")(
      "strict", po::bool_switch(), "treat URDF warnings as errors");
}

Model loadRobotFromOptions(const po::variables_map& vm) {
  std::vector<std::string> warnings;
  Model model = loadRobot(vm["robot"].as<std::string>(),
                          {vm["drives"].as<bool>(), vm["strict"].as<bool>()}, &warnings);
  for (const std::string& w : warnings) std::cerr << "warning: " << w << "\n";
  return model;
}

}  // namespace dynid::cli
