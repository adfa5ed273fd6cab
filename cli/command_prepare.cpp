// dynid prepare: a raw log (a table, or one file per signal) into dynid dataset CSVs.
#include <cmath>
#include <iostream>

#include "cli/command_floating.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "data/bags/bag.hpp"
#include "data/robots.hpp"
#include "data/scratch.hpp"
#include "reports/output.hpp"
#include "reports/prepare_report.hpp"

namespace dynid::cli {

namespace {

void addPrepareOptions(po::options_description& options) {
  const PrepareOptions d;  // every default is the options' own
  options.add_options()("log", po::value<std::vector<std::string>>()->multitoken(),
                        "delimited tables (header optional), or recordings of "
                        "sensor_msgs/JointState: ROS 2 .mcap or .db3 files or rosbag2 bag "
                        "directories (metadata.yaml, split files), ROS 1 .bag files; several: "
                        "separate recordings")(
      "effort-log", po::value<std::string>(),
      "recordings whose JointState messages carry no effort: a table of torques (--tau) or "
      "currents (--current) against --time in seconds on the recording's clock, interpolated "
      "at the position stamps")("time", po::value<std::string>()->default_value("1"),
                                "table: time column (name or index)")(
      "q", po::value<std::string>(), "table: q columns (names, 1-based indices or globs: q*)")(
      "dq", po::value<std::string>(), "table: dq columns (default: derived from q)")(
      "ddq", po::value<std::string>(), "table: ddq columns (default: derived)")(
      "tau", po::value<std::string>(), "table: torque columns")(
      "current", po::value<std::string>(), "table: motor current columns [A], instead of --tau")(
      "time-file", po::value<std::string>(), "one value per line: time")(
      "q-file", po::value<std::string>(), "one value per line, --joints per sample: q")(
      "dq-file", po::value<std::string>(), "same layout: dq (default: derived from q)")(
      "ddq-file", po::value<std::string>(), "same layout: ddq (default: derived)")(
      "tau-file", po::value<std::string>(), "same layout: torques")(
      "current-file", po::value<std::string>(), "same layout: motor currents [A]")(
      "torque-constants", po::value<std::string>(), "with currents: N m/A per joint")(
      "gear-ratios", po::value<std::string>(), "with currents: per joint (default 1)")(
      "joints", po::value<int>()->default_value(LogSource{}.num_joints))(
      "time-unit", po::value<std::string>()->default_value("s"), "s, ms, us or ns")(
      "angle-unit", po::value<std::string>()->default_value("rad"), "rad or deg (q and dq)")(
      "rate", po::value<double>()->default_value(d.rate))(
      "cutoff", po::value<std::string>()->default_value("default"),
      "low-pass [Hz], 0 (none), auto (from q's spectrum) or default (10, rate/4 below 40 Hz)")(
      "tau-cutoff", po::value<std::string>(),
      "torque's own low-pass [Hz], or none (the raw resampled torque); default: --cutoff's")(
      "order", po::value<int>()->default_value(d.order))(
      "decimate", po::value<int>()->default_value(d.decimate))(
      "max-gap", po::value<double>()->default_value(d.max_gap))(
      "trim", po::value<double>()->default_value(d.trim))("derive-dq", po::bool_switch(),
                                                          "dq from q even when logged")(
      "derive-ddq", po::bool_switch(), "ddq by differentiation even when logged")(
      "derivative", po::value<std::string>()->default_value("central"),
      "central (differences) or savgol (Savitzky-Golay)")(
      "savgol-window", po::value<int>()->default_value(d.savgol_window))(
      "savgol-degree", po::value<int>()->default_value(d.savgol_degree))(
      "keep-stalled", po::bool_switch(), "keep samples repeating the previous one exactly")(
      "skip-missing", po::bool_switch(),
      "tables: leave out rows whose selected field is empty, nan or inf (a logger's dropouts), "
      "counted and warned about, instead of refusing the log")(
      "decimal-comma", po::bool_switch(),
      "tables: numbers written with ',' for the decimal point (fields separated by ';', tab or "
      "blanks), as European spreadsheets export them")(
      "keep-raw-torque", po::bool_switch(),
      "also write validate_raw.csv: the held-out part's raw torques at the log's own stamps "
      "(unfiltered), for predict --raw and identify --validate-raw")(
      "window", po::value<std::string>(),
      "keep only these times [s from the log's first stamp], e.g. 12.5:80,95:140")(
      "rows", po::value<std::string>(), "keep only these data rows (1-based), e.g. 200:9000")(
      "robot", po::value<std::string>(),
      "the robot logged: its joint count is checked, and --dq-max and --ddq-max default to 3 "
      "times its limits")(
      "dq-max", po::value<std::string>(),
      "plausible |dq| [rad/s]: one value or one per joint (default 50, or 3 x --robot's limits)")(
      "ddq-max", po::value<std::string>(),
      "plausible |ddq| [rad/s^2]: one or one per joint (default 2000, or 3 x --robot's limits)")(
      "validate-fraction", po::value<double>()->default_value(d.validate_fraction))(
      "validate-runs", po::value<std::string>(), "hold out whole runs: 1-based, e.g. 3,4")(
      "validate-time", po::value<std::string>(), "hold out time ranges [s], e.g. 30:45,80:90")(
      "out", po::value<std::string>()->required(), "output directory")(
      "floating-base", po::bool_switch(),
      "the robot (--robot, a URDF) floats: one recording's JointState, sensor_msgs/Imu (on the "
      "base body) and geometry_msgs/WrenchStamped topics into floating_dataset.csv "
      "(docs/FLOATING.md)")("imu-topic", po::value<std::string>(),
                            "with --floating-base: the Imu topic (default: the only one)")(
      "wrench-topics", po::value<std::string>(),
      "with --floating-base: the WrenchStamped topics, comma-separated (default: every one)")(
      "contact-threshold", po::value<double>()->default_value(0.0))(
      "contact-topics", po::value<std::string>(),
      "with --floating-base: std_msgs/Bool topics as contact flags, TOPIC=FRAME comma-separated "
      "(e.g. /lf_contact=LF_FOOT)");
}

std::string text(const po::variables_map& vm, const char* key) {
  return vm.count(key) ? vm[key].as<std::string>() : std::string();
}

/// Where the signals are, and the usage errors of their options.
LogSource logSource(const po::variables_map& vm) {
  LogSource source;
  if (vm.count("log")) source.tables = vm["log"].as<std::vector<std::string>>();
  std::size_t recordings = 0;
  for (const std::string& table : source.tables) recordings += bags::isBag(table) ? 1 : 0;
  refuseUnused(vm, recordings > 0,
               {"topic", "effort-topic", "effort-log", "joint-prefix", "joint-names"},
               "applies to recordings (.mcap, .db3, .bag, bag directories)");
  if (recordings > 0) {
    if (recordings != source.tables.size())
      throw UsageError(
          "--log: give tables or recordings (.mcap, .db3, .bag, bag directories), not both");
    refuseUnused(vm, false, {"q", "dq", "ddq", "time-unit", "joints"},
                 "applies to tables: a recording's stamps, positions, velocities and efforts "
                 "come from its JointState messages, joints matched by name to --robot's");
    if (vm.count("effort-topic") && vm.count("effort-log"))
      throw UsageError("give --effort-topic or --effort-log, not both");
    refuseUnused(vm, vm.count("effort-log") > 0, {"tau", "current"},
                 "applies to a recording's --effort-log (its torque or current columns)");
    if (!vm["time"].defaulted() && !vm.count("effort-log"))
      throw UsageError("--time applies to tables and to a recording's --effort-log");
    if (vm.count("effort-log")) {
      if (vm.count("tau") + vm.count("current") != 1)
        throw UsageError("--effort-log: give its torque columns (--tau) or currents (--current)");
      source.effort_table = text(vm, "effort-log");
      source.time_column = text(vm, "time");
      source.current = vm.count("current") > 0;
      source.tau_columns = source.current ? text(vm, "current") : text(vm, "tau");
    }
    if (vm.count("effort-topic")) source.effort_topic = text(vm, "effort-topic");
    if (vm.count("topic")) source.topic = text(vm, "topic");
    if (vm.count("joint-prefix")) source.joint_prefix = text(vm, "joint-prefix");
    source.receive_time = receiveTimeOption(vm);
    return source;
  }
  if (!vm["stamp"].defaulted())
    throw UsageError(
        "--stamp applies to recordings (.mcap, .db3, .bag, bag directories), not to tables");
  if (vm.count("tau") + vm.count("current") + vm.count("tau-file") + vm.count("current-file") != 1)
    throw UsageError("give one of --tau, --current, --tau-file or --current-file");
  source.time_column = text(vm, "time");
  source.q_columns = text(vm, "q");
  source.dq_columns = text(vm, "dq");
  source.tau_columns = vm.count("current") ? text(vm, "current") : text(vm, "tau");
  source.time_file = text(vm, "time-file");
  source.q_file = text(vm, "q-file");
  source.dq_file = text(vm, "dq-file");
  source.tau_file = vm.count("current-file") ? text(vm, "current-file") : text(vm, "tau-file");
  source.num_joints = vm["joints"].as<int>();
  source.current = vm.count("current") + vm.count("current-file") > 0;
  source.ddq_columns = text(vm, "ddq");
  source.ddq_file = text(vm, "ddq-file");
  source.skip_missing = vm["skip-missing"].as<bool>();
  source.decimal_comma = vm["decimal-comma"].as<bool>();
  if (source.tables.empty() == source.q_file.empty())
    throw UsageError("give either --log (tables) or --q-file (one file per signal)");
  refuseUnused(vm, source.tables.empty(),
               {"time-file", "dq-file", "ddq-file", "tau-file", "current-file"},
               "applies to one-file-per-signal logs (--q-file), not to --log tables");
  refuseUnused(vm, !source.tables.empty(), {"time", "q", "dq", "ddq", "tau", "current"},
               "selects --log table columns; with --q-file give --time-file, --dq-file, ...");
  if (!source.tables.empty() && (source.q_columns.empty() || source.tau_columns.empty()))
    throw UsageError("a table needs --q and --tau (or --current) column selectors");
  if (source.tables.empty() && source.num_joints <= 0)
    throw UsageError(
        "one-file-per-signal logs need --joints N (the values per sample in each file)");
  if (source.current != (vm.count("torque-constants") > 0))
    throw UsageError(source.current ? "motor currents need --torque-constants (N m/A per joint)"
                                    : "--torque-constants applies to --current or --current-file");
  if (vm.count("gear-ratios") && !source.current)
    throw UsageError("--gear-ratios applies to --current or --current-file");
  return source;
}

/// Units, rate, filter and derivatives.
void readProcessing(const po::variables_map& vm, PrepareOptions& o) {
  o.time_scale = parseOption(vm, "time-unit", timeUnitScale);
  o.angle_scale = parseOption(vm, "angle-unit", angleUnitScale);
  o.rate = vm["rate"].as<double>();
  const std::string cutoff = text(vm, "cutoff");
  o.auto_cutoff = cutoff == "auto";
  if (!o.auto_cutoff && cutoff != "default") {
    const std::vector<double> value = parseList(cutoff, "cutoff");
    if (value.size() != 1 || !(value[0] >= 0.0))
      throw UsageError("--cutoff must be a frequency >= 0 [Hz], auto or default, not '" + cutoff +
                       "'");
    o.cutoff = value[0];
  }
  if (vm.count("tau-cutoff")) {
    const std::string tau_cutoff = text(vm, "tau-cutoff");
    const std::vector<double> value =
        tau_cutoff == "none" ? std::vector<double>{0.0} : parseList(tau_cutoff, "tau-cutoff");
    if (value.size() != 1 || !(value[0] >= 0.0))
      throw UsageError("--tau-cutoff must be a frequency >= 0 [Hz] or none, not '" + tau_cutoff +
                       "'");
    o.tau_cutoff = value[0];
  }
  const std::string derivative = text(vm, "derivative");
  if (derivative != "central" && derivative != "savgol")
    throw UsageError("--derivative must be central or savgol, not '" + derivative + "'");
  o.savitzky_golay = derivative == "savgol";
  refuseUnused(vm, o.savitzky_golay, {"savgol-window", "savgol-degree"},
               "applies to --derivative savgol, not central");
  refuseUnused(vm, o.auto_cutoff || o.cutoff != 0.0 || o.tau_cutoff > 0.0, {"order"},
               "applies to a filter; --cutoff 0 has none");
  o.savgol_window = vm["savgol-window"].as<int>();
  o.savgol_degree = vm["savgol-degree"].as<int>();
  o.order = vm["order"].as<int>();
  o.decimate = vm["decimate"].as<int>();
  o.max_gap = vm["max-gap"].as<double>();
  o.trim = vm["trim"].as<double>();
  o.derive_dq = vm["derive-dq"].as<bool>();
  o.derive_ddq = vm["derive-ddq"].as<bool>();
  o.keep_stalled = vm["keep-stalled"].as<bool>();
  o.keep_raw_torque = vm["keep-raw-torque"].as<bool>();
  if (o.keep_raw_torque && vm["validate-fraction"].defaulted() && !vm.count("validate-runs") &&
      !vm.count("validate-time"))
    throw UsageError(
        "--keep-raw-torque keeps the held-out part's raw torques: hold a part out "
        "(--validate-fraction, --validate-time or --validate-runs)");
  for (const auto& [key, target] : {std::pair{"torque-constants", &o.torque_constants},
                                    std::pair{"gear-ratios", &o.gear_ratios}})
    if (vm.count(key)) {
      const std::vector<double> values = parseList(text(vm, key), key);
      *target = Eigen::Map<const Eigen::VectorXd>(values.data(),
                                                  static_cast<Eigen::Index>(values.size()));
    }
}

/// "a:b,c:d" as pairs, each a < b (`what` names the option).
std::vector<std::pair<double, double>> parseRanges(std::string text, const char* what) {
  for (char& c : text) c = c == ':' ? ',' : c;
  const std::vector<double> bounds = parseList(text, what);
  if (bounds.size() % 2 != 0)
    throw UsageError(std::string("--") + what + ": ranges are from:to pairs");
  std::vector<std::pair<double, double>> out;
  for (std::size_t k = 0; k + 1 < bounds.size(); k += 2) {
    if (!(bounds[k] < bounds[k + 1]))
      throw UsageError(std::string("--") + what + ": each range is from:to with from < to");
    out.emplace_back(bounds[k], bounds[k + 1]);
  }
  return out;
}

/// The parts of the log kept, and the plausibility bounds (from --robot's limits by default).
void readWindowsAndBounds(const po::variables_map& vm, LogSource& source, PrepareOptions& o) {
  if (vm.count("window")) o.windows = parseRanges(text(vm, "window"), "window");
  if (vm.count("rows"))
    for (const auto& [from, to] : parseRanges(text(vm, "rows"), "rows")) {
      if (from < 1 || from != std::floor(from) || to != std::floor(to) || to > 1e15)
        throw UsageError("--rows: rows are whole numbers from 1, e.g. 200:9000");
      o.row_windows.emplace_back(static_cast<long>(from), static_cast<long>(to));
    }
  for (const auto& [key, target] :
       {std::pair{"dq-max", &o.dq_bound}, std::pair{"ddq-max", &o.ddq_bound}})
    if (vm.count(key)) {
      const std::vector<double> values = parseList(text(vm, key), key);
      *target = Eigen::Map<const Eigen::VectorXd>(values.data(),
                                                  static_cast<Eigen::Index>(values.size()));
    }
  if (!vm.count("robot")) {
    source.joint_names = jointNamesOption(vm, source.num_joints);
    return;
  }
  std::vector<std::string> warnings;
  const Model robot = loadRobot(text(vm, "robot"), {}, &warnings);
  printWarnings(warnings);
  const int n = robot.numJoints();
  if (source.num_joints > 0 && source.num_joints != n)
    throw UsageError("--joints " + std::to_string(source.num_joints) + " but --robot has " +
                     std::to_string(n) + " joints");
  source.num_joints = n;  // the selectors must match one column per joint
  // A recording's joints, matched by name: the robot's own, or the messages' names for them.
  source.joint_names = jointNamesOption(vm, n);
  if (source.joint_names.empty()) source.joint_names = robot.joint_names;
  for (const auto& [limit, target] : {std::pair{&JointLimits::velocity, &o.dq_bound},
                                      std::pair{&JointLimits::acceleration, &o.ddq_bound}})
    if (target->size() == 0) {
      const double fallback =
          limit == &JointLimits::velocity ? kPlausibleSpeed : kPlausibleAcceleration;
      target->resize(n);
      for (int j = 0; j < n; ++j) {
        const auto k = static_cast<std::size_t>(j);
        const double value = k < robot.limits.size() ? robot.limits[k].*limit : 0.0;
        (*target)[j] = std::isfinite(value) && value > 0.0 ? 3.0 * value : fallback;
      }
    }
}

/// What is held out for validation.
void readHoldOut(const po::variables_map& vm, PrepareOptions& o) {
  o.validate_fraction = vm["validate-fraction"].as<double>();
  if (vm.count("validate-runs"))
    for (double r : parseList(text(vm, "validate-runs"), "validate-runs")) {
      if (r < 1 || r != std::floor(r)) throw UsageError("--validate-runs: runs count from 1");
      o.validate_runs.push_back(static_cast<int>(r) - 1);
    }
  if (vm.count("validate-time"))
    o.validate_ranges = parseRanges(text(vm, "validate-time"), "validate-time");
}

}  // namespace

int runPrepare(const std::vector<std::string>& args) {
  po::options_description options("dynid prepare");
  addPrepareOptions(options);
  addRecordingOptions(options);
  addThreadsOption(options);  // the joints are prepared and the datasets' rows formatted on them
  po::variables_map vm;
  const std::string usage =
      "dynid prepare (--log log.csv... --q SEL --tau SEL | --log "
      "rec.mcap|rec.db3|bag_dir|rec.bag... [--robot R] "
      "| --time-file F --q-file F --tau-file F --joints N "
      "| --floating-base --robot URDF --log rec) --out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  outputDirectoryOption(vm);  // before the work, not after it
  if (vm["floating-base"].as<bool>()) return runFloatingPrepare(vm);
  refuseFloatingOptions(vm, {"imu-topic", "wrench-topics", "contact-threshold", "contact-topics"});
  LogSource source = logSource(vm);
  PrepareOptions o;
  readProcessing(vm, o);
  readWindowsAndBounds(vm, source, o);
  readHoldOut(vm, o);
  // The datasets in a scratch file beside the output (memory independent of the log's length).
  PrepareOutcome outcome = prepareLog(source, o, threadsOption(vm),
                                      nearestExistingDirectory(vm["out"].as<std::string>()));
  cliTexts(outcome.warnings);  // the fields they name, as this command's flags
  outcome.cutoff_reason = cliText(outcome.cutoff_reason);
  printWarnings(outcome.warnings, "dynid prepare: warning: ");
  std::cout << writePrepared(vm["out"].as<std::string>(), source, o, outcome, threadsOption(vm));
  return kExitOk;
}

}  // namespace dynid::cli
