// dynid monitor: an identified model watching a log, or samples streamed on stdin, for external
// torques (collisions, pushes), with thresholds from a clean calibration log.
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <optional>

#include "analysis/monitor/monitor.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/spelling.hpp"
#include "core/errors.hpp"
#include "data/bags/bag.hpp"
#include "data/json_number.hpp"
#include "reports/monitor_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

namespace {

/// Standard input line by line, waiting in poll() so that Ctrl-C (the flag) ends a wait for a
/// robot that sends nothing. A last line without its newline is an error: the stream was cut.
class StdinLines {
 public:
  explicit StdinLines(const std::atomic<bool>* stop) : stop_(stop) {}
  bool next(std::string& line) {
    while (true) {
      const std::size_t newline = buffer_.find('\n', start_);
      if (newline != std::string::npos) {
        line.assign(buffer_, start_, newline - start_);
        start_ = newline + 1;
        ++number_;
        return true;
      }
      buffer_.erase(0, start_);
      start_ = 0;
      if (buffer_.size() > (std::size_t{1} << 24))
        throw ParseError("<stdin>", static_cast<int>(number_ + 1), "",
                         "a line longer than 16 MiB: not a sample stream");
      if (eof_) {
        if (!buffer_.empty())
          throw ParseError("<stdin>", static_cast<int>(number_ + 1), "",
                           "the stream ended in the middle of a line (" +
                               std::to_string(buffer_.size()) + " bytes without a newline)");
        return false;
      }
      if (stop_ && stop_->load()) return false;
      pollfd fd{STDIN_FILENO, POLLIN, 0};
      const int ready = ::poll(&fd, 1, 100);
      if (ready < 0 && errno != EINTR) throw Error(std::string("<stdin>: ") + std::strerror(errno));
      if (ready <= 0) continue;
      char block[65536];
      const ssize_t got = ::read(STDIN_FILENO, block, sizeof block);
      if (got < 0) {
        if (errno == EINTR || errno == EAGAIN) continue;
        throw Error(std::string("<stdin>: ") + std::strerror(errno));
      }
      if (got == 0)
        eof_ = true;
      else
        buffer_.append(block, static_cast<std::size_t>(got));
    }
  }

 private:
  const std::atomic<bool>* stop_;
  std::string buffer_;
  std::size_t start_ = 0;
  long long number_ = 0;
  bool eof_ = false;
};

/// Events as JSON lines on stdout, flushed at once (a start within the sample that crossed).
class PrintedEvents : public MonitorEventSink {
 public:
  void started(const MonitorEvent& e) override {
    nlohmann::json line = monitorEventJson(e);
    line["event"] = "start";
    line.erase("end");
    line.erase("energy");
    line.erase("open");
    std::cout << jsonText(line) << std::endl;
  }
  void ended(const MonitorEvent& e) override {
    nlohmann::json line = monitorEventJson(e);
    line["event"] = "end";
    std::cout << jsonText(line) << std::endl;
  }
};

void addMonitorOptions(po::options_description& options) {
  options.add_options()(
      "arm", po::value<std::string>()->required(),
      "the model: identify's estimate.json, an identified URDF, a dynid .json model or a robot")(
      "robot", po::value<std::string>(), "for an estimate: the robot (default: the one it names)")(
      "data", po::value<std::string>()->required(),
      "the log to watch: a dataset CSV, a recording (.mcap, .db3, .bag or a bag directory: "
      "sensor_msgs/JointState with position, velocity and effort, joints matched by name, taken "
      "raw at their stamps), or - for samples on stdin, one line each: t,q1..qn,dq1..dqn,"
      "tau1..taun after that header (or the dataset's, with ddq)")(
      "calibration", po::value<std::string>(),
      "a clean log (dataset CSV or recording) of the same robot (no contact): the thresholds are "
      "set on it")("thresholds", po::value<std::string>(),
                   "a thresholds.json from an earlier monitor (instead of --calibration)")(
      "residual", po::value<std::string>()->default_value("observer"),
      "observer (generalized momentum: q, dq, tau) or direct (tau - model, needs ddq)")(
      "gain", po::value<std::string>(),
      "observer gain per joint [1/s] (one value for all; default 100: a 10 ms time constant)")(
      "false-alarms-per-hour", po::value<double>()->default_value(kDefaultFalseAlarmsPerHour))(
      "hold", po::value<double>()->default_value(kDefaultEventHold))(
      "max-gap", po::value<double>()->default_value(kDefaultMaxGap))(
      "torque-constants", po::value<std::string>(),
      "the efforts of a recording or of stdin samples are motor currents: N m/A per joint "
      "(torque = current x constant x gear ratio, as prepare --current)")(
      "gear-ratios", po::value<std::string>(), "with --torque-constants: per joint (default 1)")(
      "truth", po::value<std::string>(),
      "simulate --disturbance's ground truth (t,tau_ext1..): detections, delays, false alarms")(
      "out", po::value<std::string>(),
      "output directory: monitor.json, thresholds.json, report.md, report.html (required unless "
      "--data -)");
  addRecordingOptions(options);
  addThreadsOption(options);
}

/// The request the options describe (usage errors for options that do not go together).
MonitorRequest monitorRequestOf(const po::variables_map& vm) {
  MonitorRequest request;
  request.arm = vm["arm"].as<std::string>();
  if (vm.count("robot")) request.robot_spec = vm["robot"].as<std::string>();
  request.data_file = vm["data"].as<std::string>();
  if (vm.count("calibration") == vm.count("thresholds"))
    throw UsageError("give --calibration CLEAN.csv or --thresholds thresholds.json (one of them)");
  if (vm.count("calibration")) request.calibration_file = vm["calibration"].as<std::string>();
  if (vm.count("thresholds")) request.thresholds_file = vm["thresholds"].as<std::string>();
  refuseUnused(vm, vm.count("calibration") > 0, {"false-alarms-per-hour"},
               "applies with --calibration");
  const bool recording = bags::isBag(request.data_file) || (!request.calibration_file.empty() &&
                                                            bags::isBag(request.calibration_file));
  refuseUnused(vm, recording, {"topic", "stamp", "effort-topic", "joint-prefix", "joint-names"},
               "applies to recordings (.mcap, .db3, .bag, bag directories)");
  if (vm.count("topic")) request.topic = vm["topic"].as<std::string>();
  if (vm.count("joint-prefix")) request.joint_prefix = vm["joint-prefix"].as<std::string>();
  request.joint_names = jointNamesOption(vm, 0);  // counted against the arm by monitorRun
  if (vm.count("effort-topic")) request.effort_topic = vm["effort-topic"].as<std::string>();
  request.receive_time = receiveTimeOption(vm);
  if (vm.count("truth")) request.truth_file = vm["truth"].as<std::string>();
  const std::string residual = vm["residual"].as<std::string>();
  if (residual != "observer" && residual != "direct")
    throw UsageError("--residual must be observer or direct, not '" + residual + "'");
  request.residual = residual == "direct" ? MonitorResidual::kDirect : MonitorResidual::kObserver;
  if (vm.count("gain")) {
    const std::vector<double> gain = parseList(vm["gain"].as<std::string>(), "gain");
    for (double g : gain)
      if (!(g > 0.0 && g <= 1e6))
        throw UsageError("--gain: each value must be > 0 and at most 1e6 [1/s]");
    request.gain =
        Eigen::Map<const Eigen::VectorXd>(gain.data(), static_cast<Eigen::Index>(gain.size()));
  }
  if (vm.count("gear-ratios") && !vm.count("torque-constants"))
    throw UsageError("--gear-ratios applies to motor currents: give --torque-constants too");
  for (const auto& [key, target] : {std::pair{"torque-constants", &request.torque_constants},
                                    std::pair{"gear-ratios", &request.gear_ratios}})
    if (vm.count(key)) {
      const std::vector<double> values = parseList(vm[key].as<std::string>(), key);
      *target = Eigen::Map<const Eigen::VectorXd>(values.data(),
                                                  static_cast<Eigen::Index>(values.size()));
    }
  request.false_alarms_per_hour = vm["false-alarms-per-hour"].as<double>();
  request.hold = vm["hold"].as<double>();
  request.max_gap = vm["max-gap"].as<double>();
  request.threads = threadsOption(vm);
  return request;
}

}  // namespace

int runMonitor(const std::vector<std::string>& args) {
  po::options_description options("dynid monitor");
  addMonitorOptions(options);
  po::variables_map vm;
  const std::string usage =
      "dynid monitor --arm estimate.json --data log.csv --calibration clean.csv --out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  MonitorRequest request = monitorRequestOf(vm);
  const bool streamed = request.data_file == "-";
  if (!streamed && !vm.count("out")) throw UsageError("--out is required (unless --data -)");
  const std::string dir = vm.count("out") ? outputDirectoryOption(vm) : "";

  InterruptGuard interrupt;
  request.control.stop = interrupt.flag();
  StdinLines lines(interrupt.flag());
  PrintedEvents printed;
  if (streamed) {
    request.next_line = [&](std::string& line) { return lines.next(line); };
    request.sink = &printed;
  }
  std::optional<MonitorOutcome> run;
  try {
    run.emplace(monitorRun(request));
  } catch (const Error&) {
    if (!interrupt.interrupted()) throw;
    std::cerr << "dynid monitor: interrupted (Ctrl-C) before the thresholds were set: nothing "
                 "written\n";
    return kExitInterrupted;
  }
  MonitorOutcome& outcome = *run;
  cliTexts(outcome.warnings);  // the fields they name, as this command's flags
  const std::string summary =
      dir.empty() ? monitorSummary(outcome) : writeMonitor(dir, outcome, request.data_file);
  (streamed ? std::cerr : std::cout) << summary;
  return exitAfter(
      interrupt, "monitor",
      dir.empty() ? "the events so far are above" : "wrote the events so far to " + dir);
}

}  // namespace dynid::cli
