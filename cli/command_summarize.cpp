// dynid summarize: least-squares summaries of logs (one per log, or one merged), what dynid
// identify --summaries estimates from as it would from the logs themselves.
#include <filesystem>
#include <iostream>
#include <set>

#include "analysis/runs/summarize.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "reports/output.hpp"
#include "reports/summary_report.hpp"

namespace dynid::cli {

namespace {

/// Each log's summary file name: its file name's stem + ".summary.json". UsageError for two logs
/// of one name (robot_a/run1.csv and robot_b/run1.csv: --merge, or one command per robot).
std::vector<std::string> summaryNames(const std::vector<std::string>& logs) {
  std::vector<std::string> out;
  std::set<std::string> seen;
  for (const std::string& log : logs) {
    const std::string name = std::filesystem::path(log).stem().string() + ".summary.json";
    if (!seen.insert(name).second)
      throw UsageError("two logs would both be summarized as '" + name +
                       "' in --out; give --merge (one summary of them all) or summarize them "
                       "apart");
    out.push_back(name);
  }
  return out;
}

}  // namespace

int runSummarize(const std::vector<std::string>& args) {
  po::options_description options("dynid summarize");
  addRobotOptions(options, true);
  addStructuralOptions(options);
  options.add_options()(
      "data", po::value<std::vector<std::string>>()->multitoken()->required(),
      "the logs (dataset CSVs, e.g. dynid prepare's train.csv), one summary each")(
      "merge", po::bool_switch(), "one summary of every log (summary.json) instead of one each")(
      "out", po::value<std::string>()->required(),
      "output directory: <log>.summary.json per log, or summary.json with --merge");
  addTorqueFilterOption(options,
                        "the low-pass each log's torque went through (default: the prepare.json "
                        "beside it says), whose effect on the friction columns the fit reproduces");
  addRestVelocityOption(options);
  addThreadsOption(options);
  po::variables_map vm;
  if (!parseCommandLine(args, options,
                        "dynid summarize --robot R [--drive-terms T] --data LOG... [--merge] "
                        "--out DIR",
                        vm))
    return kExitOk;
  const std::string dir = outputDirectoryOption(vm);
  checkOutputDirectory(dir);
  SummarizeRequest request;
  request.model = loadRobotFromOptions(vm);
  request.robot_spec = vm["robot"].as<std::string>();
  request.structural = structuralOptions(vm);
  request.data_files = vm["data"].as<std::vector<std::string>>();
  request.rest_velocity = restVelocityOption(vm, request.model.numJoints());
  request.torque_filter = torqueFilterOption(vm);
  request.threads = threadsOption(vm);
  const bool merge = vm["merge"].as<bool>();
  const std::vector<std::string> names =
      merge ? std::vector<std::string>{"summary.json"} : summaryNames(request.data_files);
  if (stderrIsTerminal())
    request.control.progress = [](const std::string& line) {
      std::cerr << "[summarize] " << line << "\n";
    };
  InterruptGuard guard;
  request.control.stop = guard.flag();
  SummarizeOutcome outcome = summarizeRun(request);
  std::vector<std::pair<std::string, Summary>> named;
  if (merge && !outcome.summaries.empty()) {
    std::vector<const Summary*> all;
    for (const Summary& s : outcome.summaries) all.push_back(&s);
    named.emplace_back(names.front(), mergeSummaries(all, request.data_files));
  } else {
    for (std::size_t i = 0; i < outcome.summaries.size(); ++i)
      named.emplace_back(names[i], std::move(outcome.summaries[i]));
  }
  if (!named.empty()) std::cout << writeSummaries(dir, named);
  return exitAfter(guard, "summarize",
                   "the summaries of the " + std::to_string(outcome.summaries.size()) +
                       " logs read whole are written");
}

}  // namespace dynid::cli
