// dynid batch: a grid of study runs (analysis/studies/batch.hpp) in parallel worker processes,
// resumable, sharded for cluster schedulers, with one results table. See docs/BATCH.md.
#include <sys/prctl.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <iostream>
#include <sstream>

#include "analysis/studies/batch.hpp"
#include "cli/batch_workers.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "core/format.hpp"
#include "reports/batch_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

namespace {

/// dynid batch run: one run in this process (batch's worker).
int runOne(const std::vector<std::string>& args) {
  po::options_description options("dynid batch run");
  options.add_options()("spec", po::value<std::string>()->required(), "the run's spec (JSON)")(
      "out", po::value<std::string>()->required(), "result file, or - for standard output")(
      "parent", po::value<long>(), "end with this process (batch's pid)");
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid batch run --spec JSON --out FILE (batch's worker)",
                        vm))
    return kExitOk;
  if (vm.count("parent")) {
    // SIGTERM when the batch dies, however it dies (the handler removes this run's temporaries);
    // a batch already gone before this line: end now.
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != static_cast<pid_t>(vm["parent"].as<long>())) return kExitError;
  }
  nlohmann::json spec;
  try {
    spec = nlohmann::json::parse(vm["spec"].as<std::string>());
  } catch (const nlohmann::json::exception& e) {  // parse_error or out_of_range (1e400)
    throw UsageError(std::string("--spec is not JSON: ") + e.what());
  }
  writeOutput(vm["out"].as<std::string>(), batchRunDocument(runBatchSpec(spec)));
  return kExitOk;
}

/// dynid batch merge DIR... --out DIR
int runMerge(const std::vector<std::string>& args) {
  po::options_description options("dynid batch merge");
  options.add_options()("dirs", po::value<std::vector<std::string>>()->multitoken()->required(),
                        "shard output directories")("out", po::value<std::string>()->required(),
                                                    "merged output directory")(
      "allow-missing", po::bool_switch(),
      "merge what is there when runs or shards are missing (they are listed in results.json)");
  po::positional_options_description positional;
  positional.add("dirs", -1);
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid batch merge DIR... [--allow-missing] --out DIR", vm,
                        &positional))
    return kExitOk;
  const std::string out = outputDirectoryOption(vm);
  const BatchOutcome merged =
      mergeBatches(vm["dirs"].as<std::vector<std::string>>(), vm["allow-missing"].as<bool>());
  std::vector<std::pair<std::string, std::string>> runs;
  for (const auto& [name, result] : merged.done)
    runs.emplace_back(name + ".json", batchRunDocument(result));
  OutputSet run_files(out + "/runs", false);  // merged into: earlier runs stay
  for (const auto& [name, content] : runs) run_files.add(name, content);
  run_files.publish();
  writeBatchTables(out, merged);
  std::cout << "merged " << merged.done.size() << " of " << merged.total << " runs into " << out
            << "/results.csv and results.json\n";
  if (!merged.missing.empty())
    std::cerr << "dynid batch merge: " << merged.missing.size()
              << " runs missing (--allow-missing); results.json lists them\n";
  return kExitOk;
}

/// "K/N" -> (K, N), 1 <= K <= N.
std::pair<int, int> parseShard(const std::string& s) {
  int shard = 0, shards = 0;
  char slash = 0;
  std::istringstream in(s);
  if (!(in >> shard >> slash >> shards) || slash != '/' || !in.eof() || shards < 1 || shard < 1 ||
      shard > shards)
    throw UsageError("--shard must be K/N with 1 <= K <= N, not '" + s + "'");
  return {shard, shards};
}

}  // namespace

int runBatch(const std::vector<std::string>& args) {
  if (!args.empty() && args[0] == "run") return runOne({args.begin() + 1, args.end()});
  if (!args.empty() && args[0] == "merge") return runMerge({args.begin() + 1, args.end()});
  po::options_description options("dynid batch");
  options.add_options()("manifest", po::value<std::string>()->required(), "MANIFEST.json")(
      "jobs", po::value<int>()->default_value(1))("shard", po::value<std::string>(),
                                                  "K/N: only the runs whose index mod N is K - 1")(
      "quick", po::bool_switch(),
      ("every run with " + batchQuickDescription() + " (tests, trials)").c_str())(
      "out", po::value<std::string>()->required(), "output directory");
  po::positional_options_description positional;
  positional.add("manifest", 1);
  po::variables_map vm;
  const std::string usage =
      "dynid batch MANIFEST.json --jobs N [--shard K/N] [--quick] --out DIR\n"
      "       dynid batch merge DIR... --out DIR";
  if (!parseCommandLine(args, options, usage, vm, &positional)) return kExitOk;
  const int jobs = vm["jobs"].as<int>();
  const auto [shard, shards] =
      vm.count("shard") ? parseShard(vm["shard"].as<std::string>()) : std::pair{1, 1};
  const std::string dir = outputDirectoryOption(vm);
  checkOutputDirectory(dir);  // before the runs, not after them
  const BatchPlan plan =
      planBatch(vm["manifest"].as<std::string>(), dir, vm["quick"].as<bool>(), shard, shards);
  std::cerr << "dynid batch: " << plan.runs.size() << " runs in the grid, " << plan.mine.size()
            << " in this shard, " << plan.mine.size() - plan.todo.size() << " already done\n";
  const bool terminal = stderrIsTerminal();
  const InterruptGuard guard;
  const auto started = std::chrono::steady_clock::now();
  const auto secondsSince = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  const BatchOutcome outcome = runBatchWorkers(plan, jobs, guard.flag(), [&](const FinishedRun& f) {
    const std::string progress = progressText(
        static_cast<double>(f.finished) / static_cast<double>(f.todo), secondsSince(started));
    if (terminal) {
      std::cerr << "\r[batch] " << f.finished << "/" << f.todo << " runs finished; " << progress
                << "   " << std::flush;
    } else {  // a log (CI, nohup, a pipe): a line per run, so a long batch is not silent
      std::cerr << "[batch] " << f.finished << "/" << f.todo << " "
                << batchRunName(f.run, plan.runs[f.run]) << (f.ok ? " done" : " failed") << "; "
                << progress << "\n";
    }
  });
  if (terminal) std::cerr << "\n";
  writeBatchTables(dir, outcome);
  std::cout << "dynid batch: " << outcome.done.size() << " of " << plan.mine.size()
            << " runs done; wrote " << dir << "/results.csv and results.json\n";
  if (outcome.interrupted) {
    std::cerr << "dynid batch: interrupted (Ctrl-C); run the same command again to finish the "
              << outcome.missing.size() << " missing runs\n";
    return kExitInterrupted;
  }
  if (!outcome.failed.empty()) {
    std::cerr << "dynid batch: " << outcome.failed.size() << " runs failed:";
    for (const std::string& f : outcome.failed) std::cerr << " " << f;
    std::cerr << "\n";
    return kExitError;
  }
  return kExitOk;
}

}  // namespace dynid::cli
