#include "cli/common.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

#include <boost/make_shared.hpp>

#include "analysis/estimation/front.hpp"
#include "analysis/records/provenance.hpp"
#include "cli/build_info.hpp"
#include "cli/spelling.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "data/io.hpp"
#include "reports/identification_report.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

namespace {
std::atomic<bool> sigint_seen{false};
extern "C" void onInterrupt(int) { sigint_seen.store(true); }

}  // namespace

std::string versionText() { return std::string(DYNID_VERSION) + " (commit " + kBuildCommit + ")"; }

std::string selfExecutable() {
  std::error_code ec;
  const auto path = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw InputError("cannot find the dynid executable (/proc/self/exe)");
  return path.string();
}

void beginCommandRun(const std::vector<std::string>& arguments) {
  RunProvenance run;
  run.interface = "cli";
  run.version = DYNID_VERSION;
  run.commit = kBuildCommit;
  run.command = {"dynid"};
  run.command.insert(run.command.end(), arguments.begin(), arguments.end());
  std::error_code error;
  run.working_directory = std::filesystem::current_path(error).string();
  beginRun(std::move(run));
}

std::string outputDirectoryOption(const po::variables_map& vm) {
  const std::string dir = vm["out"].as<std::string>();
  if (dir == "-")
    throw UsageError(
        "--out names a directory (this command writes several files); '-' (standard output) is "
        "for commands that write one file");
  checkOutputDirectory(dir);  // before the work, not after it
  return dir;
}

std::vector<double> fixedList(const po::variables_map& vm, const char* name, std::size_t count,
                              const char* what) {
  std::vector<double> v = parseList(vm[name].as<std::string>(), name);
  if (v.size() != count) throw UsageError(std::string("--") + name + " takes " + what);
  return v;
}

void addAttachmentOptions(po::options_description& options, const std::string& what) {
  options.add_options()("link", po::value<std::string>(),
                        ("the link " + what + " is attached to (default: the last)").c_str())(
      "tool-xyz", po::value<std::string>(),
      "the attachment frame's origin in the link's frame, x,y,z [m] (default: 0,0,0)")(
      "tool-rpy", po::value<std::string>(),
      "the attachment frame's roll,pitch,yaw in the link's frame [rad] (default: 0,0,0)");
}

Pose<double> attachmentFrameOption(const po::variables_map& vm) {
  Pose<double> frame = Pose<double>::Identity();
  if (vm.count("tool-xyz")) {
    const std::vector<double> v = fixedList(vm, "tool-xyz", 3, "three numbers: x,y,z");
    frame.translation = Eigen::Vector3d(v[0], v[1], v[2]);
  }
  if (vm.count("tool-rpy")) {
    const std::vector<double> v = fixedList(vm, "tool-rpy", 3, "three numbers: roll,pitch,yaw");
    frame.rotation = rotationFromRpy(v[0], v[1], v[2]);
  }
  return frame;
}

std::vector<double> parseList(const std::string& text, const std::string& option) {
  std::vector<double> out;
  std::size_t start = 0;
  for (int entry = 1;; ++entry) {
    const std::size_t comma = text.find(',', start);
    const std::string field = text.substr(start, comma - start);
    char* end = nullptr;
    const double x = std::strtod(field.c_str(), &end);
    if (field.empty() || end != field.c_str() + field.size() || !std::isfinite(x))
      throw UsageError("--" + option + ": entry " + std::to_string(entry) + " '" + field +
                       "' is not a finite number");
    out.push_back(x);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

Eigen::VectorXd parseJointVector(const std::string& text, const std::string& option, int n,
                                 bool allow_broadcast) {
  const std::vector<double> list = parseList(text, option);
  if (allow_broadcast && list.size() == 1) return Eigen::VectorXd::Constant(n, list[0]);
  if (static_cast<int>(list.size()) != n)
    throw UsageError("--" + option + " has " + std::to_string(list.size()) +
                     " entries, the robot has " + std::to_string(n) + " joints" +
                     (allow_broadcast ? " (or give one value for all)" : ""));
  return Eigen::Map<const Eigen::VectorXd>(list.data(), n);
}

std::optional<Eigen::VectorXd> optionalJointVector(const po::variables_map& vm, const char* name,
                                                   int n, bool allow_broadcast) {
  if (!vm.count(name)) return std::nullopt;
  return parseJointVector(vm[name].as<std::string>(), name, n, allow_broadcast);
}

void addPriorWeightOption(po::options_description& options) {
  options.add_options()("prior-weight", po::value<double>()->default_value(kDefaultPriorWeight));
}

double priorWeightOption(const po::variables_map& vm) {
  return vm["prior-weight"].as<double>();  // > 0: core/option_ranges.hpp
}

void addFrontOptions(po::options_description& options, const char* front_help) {
  options.add_options()("front", po::bool_switch(), front_help)(
      "front-weights", po::value<std::string>(),
      "the front's weights, comma-separated, increasing (implies --front)")(
      "front-tolerance", po::value<double>()->default_value(0.05),
      "the chosen estimate's held-out torque error is at most this fraction above the best "
      "physically consistent one's; among those, the least held-out GC error");
}

std::vector<double> frontWeightsOption(const po::variables_map& vm) {
  if (vm.count("front-weights"))
    return parseList(vm["front-weights"].as<std::string>(), "front-weights");
  return vm["front"].as<bool>() ? defaultFrontWeights() : std::vector<double>{};
}

std::string writeUrdfSource(const po::variables_map& vm, const std::string& robot_spec) {
  if (!isUrdfSpec(robot_spec))
    throw UsageError("--write-urdf needs a robot given as a .urdf file, not '" + robot_spec + "'");
  const std::string target = vm["write-urdf"].as<std::string>();
  if (target == "-")
    throw UsageError(
        "--write-urdf writes two files (FILE and its .dynid.json); name a file, "
        "not - (standard output)");
  for (const std::string& path : {target, writeBackJsonPath(target)})
    if (isInputFile(path))
      throw UsageError("--write-urdf: '" + path +
                       "' is an input of this command; name another file (the input stays)");
  const std::filesystem::path parent = std::filesystem::path(target).parent_path();
  std::error_code error;
  const bool in_out =
      !parent.empty() && parent.lexically_normal() ==
                             std::filesystem::path(vm["out"].as<std::string>()).lexically_normal();
  if (!parent.empty() && !in_out && !std::filesystem::is_directory(parent, error))
    throw UsageError("--write-urdf: the directory '" + parent.string() +
                     "' does not exist; create it, or name a file in --out's directory");
  return robot_spec;
}

void addKeepRefinementOption(po::options_description& options) {
  options.add_options()("keep-worse-refinements", po::bool_switch(),
                        "report a refinement's result even when it ends above its search's "
                        "training GC error (default: keep the search's result then)");
}

bool keepIfBetterOption(const po::variables_map& vm) {
  return !vm["keep-worse-refinements"].as<bool>();
}

void addThreadsOption(po::options_description& options) {
  options.add_options()("threads", po::value<int>()->default_value(kAllThreads));
}

int threadsOption(const po::variables_map& vm) {
  return vm["threads"].as<int>();  // 0 to 256: core/option_ranges.hpp
}

void addRestVelocityOption(po::options_description& options) {
  options.add_options()(
      "rest-velocity", po::value<std::string>(),
      "a joint is at rest where |dq| is at most this [rad/s or m/s; one, or one per joint]: there "
      "Coulomb, asymmetry and Stribeck friction are static (predicted as zero, not fitted). "
      "Default: measured per joint from the data's velocity noise and its chatter at zero");
}

std::vector<double> restVelocityOption(const po::variables_map& vm, int joints) {
  if (!vm.count("rest-velocity")) return {};
  const std::string text = vm["rest-velocity"].as<std::string>();
  const std::vector<double> v =
      joints > 0 ? [&] {
        const Eigen::VectorXd x = parseJointVector(text, "rest-velocity", joints, true);
        return std::vector<double>(x.data(), x.data() + x.size());
      }()
                 : parseList(text, "rest-velocity");
  for (double x : v)
    if (x < 0.0) throw UsageError("--rest-velocity: a rest velocity is a speed, >= 0");
  return v;
}

void addTorqueFilterOption(po::options_description& options, const std::string& what) {
  options.add_options()(
      "torque-filter", po::value<std::string>()->default_value("auto"),
      (what + ": auto (the prepare.json beside --data; none without one), none, or "
              "CUTOFF[,ORDER] (a zero-phase Butterworth as prepare's: Hz, order 4 "
              "unless given)")
          .c_str());
}

TorqueFilterChoice torqueFilterOption(const po::variables_map& vm) {
  const std::string text = vm["torque-filter"].as<std::string>();
  if (text == "auto") return std::nullopt;
  if (text == "none") return TorqueFilter{};
  const std::vector<double> values = parseList(text, "torque-filter");
  const bool order_ok = values.size() < 2 || (values[1] >= 1.0 && values[1] <= 12.0 &&
                                              values[1] == std::floor(values[1]));
  if (values.empty() || values.size() > 2 || !(values[0] > 0.0) || !std::isfinite(values[0]) ||
      !order_ok)
    throw UsageError(
        "--torque-filter: auto, none, or CUTOFF[,ORDER] with a cutoff > 0 Hz and an "
        "order of 1 to 12, not '" +
        text + "'");
  TorqueFilter out;
  out.cutoff = values[0];
  out.order = values.size() > 1 ? static_cast<int>(values[1]) : 4;
  return out;
}

void addRecordingOptions(po::options_description& options) {
  options.add_options()("topic", po::value<std::string>(),
                        "recordings: the JointState topic (default: the only one)")(
      "stamp", po::value<std::string>()->default_value("header"),
      "recordings: header (header.stamp) or receive (when the recorder received each message)")(
      "effort-topic", po::value<std::string>(),
      "recordings whose JointState messages carry no effort: the JointState topic whose efforts "
      "are the torques (joints by name), interpolated at the position stamps")(
      "joint-prefix", po::value<std::string>(),
      "recordings: the messages name the robot's joints with this prefix (one arm of several, "
      "e.g. left_); one prefix that fits every joint alone is found without it")(
      "joint-names", po::value<std::string>(),
      "recordings: the messages' names of the robot's joints, in its joint order, comma-separated "
      "(default: --robot's own names), for a driver that names them otherwise (A1,A2,...)");
}

std::vector<std::string> nameListOption(const po::variables_map& vm, const char* option) {
  if (!vm.count(option)) return {};
  std::vector<std::string> names;
  std::stringstream list(vm[option].as<std::string>());
  for (std::string name; std::getline(list, name, ',');) {
    if (name.empty()) throw UsageError(std::string("--") + option + ": an empty name in the list");
    if (std::find(names.begin(), names.end(), name) != names.end())
      throw UsageError(std::string("--") + option + ": '" + name + "' is named twice");
    names.push_back(name);
  }
  return names;
}

std::vector<std::string> jointNamesOption(const po::variables_map& vm, int joints) {
  const std::vector<std::string> names = nameListOption(vm, "joint-names");
  if (names.empty()) return {};
  if (joints > 0 && static_cast<int>(names.size()) != joints)
    throw UsageError("--joint-names gives " + std::to_string(names.size()) +
                     " names, the robot has " + std::to_string(joints) + " joints");
  return names;
}

bool receiveTimeOption(const po::variables_map& vm) {
  const std::string stamp = vm["stamp"].as<std::string>();
  if (stamp != "header" && stamp != "receive")
    throw UsageError("--stamp must be header or receive, not '" + stamp + "'");
  return stamp == "receive";
}

void addRobotOptions(po::options_description& options, bool required) {
  po::typed_value<std::string>* robot = po::value<std::string>();
  if (required) robot->required();
  options.add_options()("robot", robot,
                        "puma560, puma560-consistent, panda, a .urdf file or a dynid .json model")(
      "drives", po::bool_switch(),
      "the robot's own drive terms (puma560: ia,fv,fc,fa; panda: fv,fc,fo; others: ia,fv,fc). "
      "Without it, a URDF with nonzero <dynamics damping friction> has fv,fc from them")(
      "drive-terms", po::value<std::string>(),
      ("exactly these drive terms, e.g. fv,fc,fo: " + driveTermHelp("; ") + "; or none").c_str())(
      "strict", po::bool_switch(), "treat URDF warnings as errors");
}

RobotOptions robotOptions(const po::variables_map& vm) {
  RobotOptions out;
  out.drives = vm["drives"].as<bool>();
  out.strict = vm["strict"].as<bool>();
  if (vm.count("drive-terms")) {
    if (out.drives) throw UsageError("give --drives or --drive-terms, not both");
    try {
      out.drive_terms = parseDriveTerms(vm["drive-terms"].as<std::string>());
    } catch (const InputError& e) {
      throw UsageError(std::string("--drive-terms: ") + e.what());
    }
  }
  return out;
}

Model loadRobotFromOptions(const po::variables_map& vm,
                           const std::vector<std::string>& fixed_joints) {
  std::vector<std::string> warnings;
  RobotOptions options = robotOptions(vm);
  options.fixed_joints = fixed_joints;
  Model model = loadRobot(vm["robot"].as<std::string>(), options, &warnings);
  printWarnings(warnings);
  return model;
}

Model loadOtherRobot(const po::variables_map& vm, const char* option) {
  return loadRobot(vm[option].as<std::string>(), robotOptions(vm));
}

void addStructuralOptions(po::options_description& options) {
  const StructuralOptions d;  // every default is the options' own
  options.add_options()("samples", po::value<int>()->default_value(d.samples))(
      "seed", po::value<std::uint64_t>()->default_value(d.seed), "seed of the random states")(
      "tolerance", po::value<double>()->default_value(d.tolerance));
}

StructuralOptions structuralOptions(const po::variables_map& vm) {
  return {vm["samples"].as<int>(), vm["seed"].as<std::uint64_t>(), vm["tolerance"].as<double>()};
}

/// `word` as one shell word: as it is when it holds only safe characters, else in single quotes.
std::string shellWord(const std::string& word) {
  const bool safe = !word.empty() && word.find_first_not_of(
                                         "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                         "0123456789_./:=,+-@%") == std::string::npos;
  if (safe) return word;
  std::string out = "'";
  for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool given(const po::variables_map& vm, const char* option) {
  return vm.count(option) > 0 && !vm[option].defaulted();
}

void refuseUnused(const po::variables_map& vm, bool used,
                  std::initializer_list<const char*> options, const std::string& applies) {
  if (used) return;
  for (const char* option : options)
    if (given(vm, option)) throw UsageError(std::string("--") + option + " " + applies);
}

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) != 0; }

InterruptGuard::InterruptGuard() {
  sigint_seen.store(false);
  previous_ = std::signal(SIGINT, onInterrupt);
}

InterruptGuard::~InterruptGuard() { std::signal(SIGINT, previous_); }

const std::atomic<bool>* InterruptGuard::flag() const { return &sigint_seen; }

bool InterruptGuard::interrupted() const { return sigint_seen.load(); }

int exitAfter(const InterruptGuard& guard, const std::string& command, const std::string& written) {
  if (!guard.interrupted()) return kExitOk;
  std::cerr << "dynid " << command << ": interrupted (Ctrl-C): " << written << "\n";
  return kExitInterrupted;
}

}  // namespace dynid::cli
