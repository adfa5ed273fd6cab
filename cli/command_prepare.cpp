// dynid prepare: a raw log (a table, or one file per signal) into dynid dataset CSVs.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "reports/prepare_report.hpp"

namespace dynid::cli {

int runPrepare(const std::vector<std::string>& args) {
  po::options_description options("dynid prepare");
  options.add_options()("log", po::value<std::string>(), "a delimited table (header optional)")(
      "time", po::value<std::string>()->default_value("1"), "table: time column (name or index)")(
      "q", po::value<std::string>(), "table: q columns (names, 1-based indices or globs: q*)")(
      "dq", po::value<std::string>(), "table: dq columns (default: derived from q)")(
      "tau", po::value<std::string>(), "table: torque columns")(
      "time-file", po::value<std::string>(), "one value per line: time")(
      "q-file", po::value<std::string>(), "one value per line, --joints per sample: q")(
      "dq-file", po::value<std::string>(), "same layout: dq (default: derived from q)")(
      "tau-file", po::value<std::string>(), "same layout: torques")(
      "joints", po::value<int>()->default_value(0), "joints (files: required)")(
      "time-unit", po::value<std::string>()->default_value("s"), "s, ms, us or ns")(
      "angle-unit", po::value<std::string>()->default_value("rad"), "rad or deg (q and dq)")(
      "rate", po::value<double>()->default_value(0.0), "resampling rate [Hz] (0: median)")(
      "cutoff", po::value<double>()->default_value(-1.0), "low-pass [Hz] (0: none; <0: 10)")(
      "order", po::value<int>()->default_value(4), "Butterworth order")(
      "decimate", po::value<int>()->default_value(1), "keep every Nth sample")(
      "max-gap", po::value<double>()->default_value(0.0), "split at longer steps [s] (0: 5 steps)")(
      "trim", po::value<double>()->default_value(-1.0), "dropped at run ends [s] (<0: 2/cutoff)")(
      "derive-dq", po::bool_switch(), "dq from q even when logged")(
      "validate-fraction", po::value<double>()->default_value(0.0),
      "hold out the last fraction of each run as validate.csv")(
      "out", po::value<std::string>()->required(), "output directory");
  po::variables_map vm;
  const std::string usage =
      "dynid prepare (--log log.csv --q SEL --tau SEL | --time-file F --q-file F --tau-file F "
      "--joints N) --out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  const auto text = [&](const char* key) {
    return vm.count(key) ? vm[key].as<std::string>() : std::string();
  };
  const LogSource source{text("log"),      text("time"),          text("q"),      text("dq"),
                         text("tau"),      text("time-file"),     text("q-file"), text("dq-file"),
                         text("tau-file"), vm["joints"].as<int>()};
  if (source.table.empty() == source.q_file.empty())
    throw UsageError("give either --log (a table) or --q-file (one file per signal)");
  if (!source.table.empty() && (source.q_columns.empty() || source.tau_columns.empty()))
    throw UsageError("a table needs --q and --tau column selectors");
  PrepareOptions o;
  o.time_scale = parseOption(vm, "time-unit", timeUnitScale);
  o.angle_scale = parseOption(vm, "angle-unit", angleUnitScale);
  o.rate = checkedOption<double>(
      vm, "rate", [](double r) { return r >= 0.0; }, ">= 0");
  o.cutoff = vm["cutoff"].as<double>();
  o.order = checkedOption<int>(
      vm, "order", [](int k) { return k >= 1 && k <= 12; }, "1 to 12");
  o.decimate = checkedOption<int>(
      vm, "decimate", [](int d) { return d >= 1; }, ">= 1");
  o.max_gap = checkedOption<double>(
      vm, "max-gap", [](double g) { return g >= 0.0; }, ">= 0");
  o.trim = vm["trim"].as<double>();
  o.derive_dq = vm["derive-dq"].as<bool>();
  o.validate_fraction = checkedOption<double>(
      vm, "validate-fraction", [](double f) { return f >= 0.0 && f < 1.0; }, "in [0, 1)");
  const PrepareOutcome outcome = prepareLog(source, o);
  std::cout << writePrepared(vm["out"].as<std::string>(), source, outcome);
  return kExitOk;
}

}  // namespace dynid::cli
