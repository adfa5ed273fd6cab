// dynid demo: the main job on the built-in PUMA 560 (analysis/demo.hpp), with its reports.
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <iostream>

#include "analysis/demo.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "data/io.hpp"
#include "reports/demo_report.hpp"

namespace dynid::cli {

namespace {
std::atomic<bool> interrupted{false};
extern "C" void onDemoInterrupt(int) { interrupted.store(true); }
}  // namespace

int runDemo(const std::vector<std::string>& args) {
  po::options_description options("dynid demo");
  options.add_options()("out", po::value<std::string>()->default_value("dynid-demo"),
                        "output directory (summary.json, report.md, report.html)")(
      "quick", po::bool_switch(), "2 s of data, 20 segments, 2 s searches (about 20 s in all)")(
      "seed", po::value<std::uint64_t>()->default_value(1),
      "seed of the initial guess and the searches")(
      "search-seconds", po::value<double>()->default_value(0.0),
      "wall time of each search (0: 30 s, 2 s with --quick)")(
      "threads", po::value<int>()->default_value(0), "threads (0: all cores)");
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid demo [--out DIR] [--quick] [--seed S]", vm))
    return kExitOk;
  if (vm["threads"].as<int>() < 0) throw UsageError("--threads must be >= 0 (0: all cores)");
  const double search_seconds = vm["search-seconds"].as<double>();
  if (!(search_seconds >= 0.0)) throw UsageError("--search-seconds must be >= 0");
  const std::string dir = vm["out"].as<std::string>();

  DemoOptions demo;
  demo.quick = vm["quick"].as<bool>();
  demo.seed = vm["seed"].as<std::uint64_t>();
  demo.threads = vm["threads"].as<int>();
  demo.search_seconds = search_seconds;
  demo.stop = &interrupted;
  const bool terminal = ::isatty(STDERR_FILENO) != 0;
  if (terminal)
    demo.progress = [](const std::string& line) { std::cerr << "[demo] " << line << "\n"; };
  interrupted.store(false);
  auto previous = std::signal(SIGINT, onDemoInterrupt);
  DemoResult result;
  try {
    result = runDemo(demo);
  } catch (...) {
    std::signal(SIGINT, previous);
    throw;
  }
  std::signal(SIGINT, previous);

  std::string warning;
  const std::vector<Figure> figures = demoFigures(result, &warning);
  if (!warning.empty()) std::cerr << "dynid demo: warning: " << warning << "\n";
  std::filesystem::create_directories(dir);
  for (const Figure& figure : figures)
    writeFileAtomically(dir + "/" + figure.name + ".svg", figure.svg);
  writeFileAtomically(dir + "/summary.json", demoSummaryJson(result));
  writeFileAtomically(dir + "/report.md", demoMarkdown(result, figures));
  writeFileAtomically(dir + "/report.html", demoHtml(result, figures));
  std::cout << demoTable(result);
  if (result.interrupted) std::cout << "interrupted: the table has the stages that finished\n";
  std::cout << "report: " << dir << "/report.html (and report.md, summary.json)\n";
  return kExitOk;
}

}  // namespace dynid::cli
