// dynid demo: the main job on the built-in PUMA 560 (analysis/studies/demo.hpp), with its reports.
#include <iostream>

#include "analysis/studies/demo.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "reports/demo_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

int runDemo(const std::vector<std::string>& args) {
  po::options_description options("dynid demo");
  const DemoOptions d;  // every default is the options' own
  options.add_options()("out", po::value<std::string>()->default_value("dynid-demo"),
                        "output directory (summary.json, report.md, report.html)")(
      "quick", po::bool_switch(), "4 s of data, 20 segments, 2 s searches (about 20 s in all)")(
      "seed", po::value<std::uint64_t>()->default_value(d.seed),
      "seed of the initial guess and the searches")(
      "search-seconds", po::value<double>()->default_value(d.search_seconds))(
      "search-evaluations", po::value<long>()->default_value(d.search_evaluations))(
      "refine-iterations", po::value<int>()->default_value(d.refine_iterations))(
      "refine-seconds", po::value<double>()->default_value(d.refine_seconds));
  addPriorWeightOption(options);
  addKeepRefinementOption(options);
  addThreadsOption(options);
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid demo [--out DIR] [--quick] [--seed S]", vm))
    return kExitOk;
  outputDirectoryOption(vm);  // before the work, not after it
  DemoOptions demo;
  demo.threads = threadsOption(vm);
  demo.search_seconds = vm["search-seconds"].as<double>();
  demo.search_evaluations = vm["search-evaluations"].as<long>();
  demo.refine_iterations = vm["refine-iterations"].as<int>();
  demo.refine_seconds = vm["refine-seconds"].as<double>();
  demo.prior_weight = priorWeightOption(vm);
  demo.keep_if_better = keepIfBetterOption(vm);
  demo.quick = vm["quick"].as<bool>();
  demo.seed = vm["seed"].as<std::uint64_t>();
  if (stderrIsTerminal())
    demo.control.progress = [](const std::string& line) { std::cerr << "[demo] " << line << "\n"; };
  const InterruptGuard guard;
  demo.control.stop = guard.flag();
  const DemoResult result = runDemo(demo);

  std::string warning;
  const std::vector<Figure> figures = demoFigures(result, &warning);
  if (!warning.empty()) std::cerr << "dynid demo: warning: " << warning << "\n";
  const std::string dir = vm["out"].as<std::string>();
  writeDemoReport(dir, result, figures);
  std::cout << demoTable(result);
  if (result.interrupted) std::cout << "interrupted: the table has the stages that finished\n";
  std::cout << "report: " << dir << "/report.html (and report.md, summary.json)\n";
  return exitAfter(guard, "demo", "the report has the stages that finished");
}

}  // namespace dynid::cli
