// Shared pieces of the dynid commands: option parsing helpers, the usage-error type and the exit
// codes (0 success, 1 runtime or data error, 2 usage error).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <boost/program_options.hpp>
#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "core/model.hpp"

namespace dynid::cli {

namespace po = boost::program_options;

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;
inline constexpr int kExitUsage = 2;

/// A mistake in the command line (exit code 2).
class UsageError : public Error {
 public:
  using Error::Error;
};

/// Parses the options of one command; prints help and returns false on --help. Throws UsageError
/// (with the usage line) on unknown or malformed options.
bool parseCommandLine(const std::vector<std::string>& args, const po::options_description& options,
                      const std::string& usage, po::variables_map& vm);

/// "0,0.785,3.14" -> {0, 0.785, 3.14}; names the option and the entry at fault.
std::vector<double> parseList(const std::string& text, const std::string& option);

/// A list of exactly n entries, or one entry broadcast to n; names the option on mismatch.
Eigen::VectorXd parseJointVector(const std::string& text, const std::string& option, int n,
                                 bool allow_broadcast);

/// The options every robot-using command takes: --robot, --drives, --strict.
void addRobotOptions(po::options_description& options);
/// Loads the robot named by --robot (warnings to stderr).
Model loadRobotFromOptions(const po::variables_map& vm);

/// A finite number, or null (JSON has no infinity or NaN).
inline nlohmann::json numberOrNull(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

}  // namespace dynid::cli
