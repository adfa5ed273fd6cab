// dynid audit: do estimates of one robot from separate sessions agree within their sigma?
#include <iostream>

#include "analysis/studies/audit.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "data/robots.hpp"
#include "reports/audit_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

int runAudit(const std::vector<std::string>& args) {
  po::options_description options("dynid audit");
  options.add_options()("estimates", po::value<std::vector<std::string>>()->multitoken(),
                        "identify's estimate.json of each session (two or more)")(
      "data", po::value<std::vector<std::string>>()->multitoken(),
      "or a dataset CSV of each session (two or more), identified here one by one")(
      "robot", po::value<std::string>(), "with --data: the robot")(
      "drive-terms", po::value<std::string>(), "with --data: its drive terms, e.g. fv,fc")(
      "method", po::value<std::string>()->default_value("ols"), "with --data: ols, wls or pc")(
      "level", po::value<double>()->default_value(kDefaultAuditLevel))(
      "out", po::value<std::string>()->required(), "output directory (audit.json, report.md)");
  addThreadsOption(options);
  po::variables_map vm;
  if (!parseCommandLine(args, options,
                        "dynid audit --estimates a/estimate.json b/estimate.json ... --out DIR",
                        vm))
    return kExitOk;
  const std::string dir = outputDirectoryOption(vm);
  checkOutputDirectory(dir);
  AuditRequest request;
  if (vm.count("estimates"))
    request.estimate_files = vm["estimates"].as<std::vector<std::string>>();
  if (vm.count("data")) request.data_files = vm["data"].as<std::vector<std::string>>();
  if (request.estimate_files.empty() == request.data_files.empty())
    throw UsageError("give the sessions as --estimates or as --data (two or more), one of them");
  if (std::max(request.estimate_files.size(), request.data_files.size()) < 2)
    throw UsageError("an audit needs two sessions or more");
  refuseUnused(vm, !request.data_files.empty(), {"robot", "drive-terms", "method"},
               "applies with --data");
  if (!request.data_files.empty()) {
    if (!vm.count("robot")) throw UsageError("--data needs --robot");
    request.robot = vm["robot"].as<std::string>();
    if (vm.count("drive-terms"))
      request.drive_terms =
          parseOption(vm, "drive-terms", [](const std::string& t) { return parseDriveTerms(t); });
    request.method = parseOption(vm, "method", [](const std::string& m) {
      return parseMethod(m, {Method::kOls, Method::kWls, Method::kPc});
    });
  }
  request.level = vm["level"].as<double>();
  request.threads = threadsOption(vm);
  std::cout << writeAudit(dir, auditRun(request));
  return kExitOk;
}

}  // namespace dynid::cli
