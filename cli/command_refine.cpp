// dynid refine: Ceres least squares on the GC residuals, from a search or identify result.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "analysis/records/provenance.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "reports/output.hpp"
#include "reports/run_report.hpp"

namespace dynid::cli {

namespace {
void addRefineOptions(po::options_description& options) {
  const RefineRequest d;  // every default is the request's own
  options.add_options()("from", po::value<std::string>()->required(),
                        "start: DIR/search.json (dynid search) or DIR/estimate.json (identify)")(
      "data", po::value<std::string>()->required(), "training dataset CSV")(
      "validate", po::value<std::string>(), "held-out dataset CSV: its GC error before and after")(
      "truth", po::value<std::string>(), "true model (robot spec), for parameter errors")(
      "estimate-initial-states", po::bool_switch(),
      "estimate each segment's start state with the parameters (noisy measured starts)")(
      "continuity-weight", po::value<double>()->default_value(d.options.continuity_weight))(
      "max-iterations", po::value<int>()->default_value(d.options.max_iterations))(
      "no-base-stage", po::bool_switch(),
      "refine the free parameters directly, without first solving in base coordinates")(
      "no-gauge", po::bool_switch(),
      "let the directions that change no base parameter move (slower; for starts at a bound)")(
      "budget-seconds", po::value<double>()->default_value(d.options.max_seconds))(
      "form", po::value<std::string>()->default_value("paper"),
      "from estimate.json: paper or standard parameters")(
      "range", po::value<double>()->default_value(d.range))(
      "horizon", po::value<double>()->default_value(d.horizon))(
      "segments", po::value<int>()->default_value(d.segments))(
      "out", po::value<std::string>()->required(), "output directory (refine.json)");
  addThreadsOption(options);
}
}  // namespace

int runRefine(const std::vector<std::string>& args) {
  po::options_description options("dynid refine");
  addRobotOptions(options);
  addRefineOptions(options);
  po::variables_map vm;
  const std::string usage =
      "dynid refine --robot R --from DIR/search.json|DIR/estimate.json --data train.csv "
      "[--estimate-initial-states] [--truth T] [--validate test.csv] --out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  outputDirectoryOption(vm);  // before the work, not after it
  refuseUnused(vm, vm["estimate-initial-states"].as<bool>(), {"continuity-weight"},
               "applies with --estimate-initial-states only");
  RefineRequest request;
  RefineOptions& refine = request.options;
  refine.max_iterations = vm["max-iterations"].as<int>();
  refine.num_threads = threadsOption(vm);
  refine.max_seconds = vm["budget-seconds"].as<double>();
  refine.continuity_weight = vm["continuity-weight"].as<double>();
  refine.estimate_initial_states = vm["estimate-initial-states"].as<bool>();
  refine.fix_gauge = !vm["no-gauge"].as<bool>();
  refine.base_stage = !vm["no-base-stage"].as<bool>();
  request.form = parseOption(vm, "form", parseParameterForm);
  request.range = vm["range"].as<double>();
  request.horizon = vm["horizon"].as<double>();
  request.segments = vm["segments"].as<int>();
  request.robot = loadRobotFromOptions(vm);
  request.robot_source = modelSourceOf(vm["robot"].as<std::string>());
  request.from_file = vm["from"].as<std::string>();
  request.data_file = vm["data"].as<std::string>();
  if (vm.count("validate")) request.validate_file = vm["validate"].as<std::string>();
  if (vm.count("truth")) request.truth = loadOtherRobot(vm, "truth");

  const InterruptGuard guard;
  request.control.stop = guard.flag();
  const bool terminal = stderrIsTerminal();
  if (terminal)
    request.options.on_iteration = [best = HUGE_VAL](const RefineIteration& it,
                                                     double done) mutable {
      best = std::min(best, it.cost);  // a rejected step reports an infinite cost
      std::fprintf(stderr, "\r[refine] %s iteration %d: best cost %s; %s   ", it.stage.c_str(),
                   it.iteration, formatNumber(best, 4).c_str(),
                   progressText(done, it.seconds).c_str());
    };
  const RefineOutcome outcome = refineRun(request);
  if (terminal) std::fprintf(stderr, "\n");
  const std::string dir = vm["out"].as<std::string>();
  writeReportFiles(dir, {{"refine.json", jsonText(withProvenance(refineJson(outcome)), 1) + "\n"}});
  printWarnings(outcome.warnings);
  if (const std::string warning = refineWarning(outcome); !warning.empty())
    std::cerr << "warning: " << warning << "\n";
  std::cout << refineSummary(outcome, dir);
  return exitAfter(guard, "refine", "wrote the best parameters so far to " + dir + "/refine.json");
}

}  // namespace dynid::cli
