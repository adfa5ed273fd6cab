// Shared pieces of the dynid commands: option parsing, the usage-error type, the exit codes
// (0 success, 1 runtime or data error, 2 usage error), the SIGINT guard and the robot options.
#pragma once

#include <atomic>
#include <csignal>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <boost/program_options.hpp>

#include "analysis/runs/identify.hpp"
#include "core/errors.hpp"
#include "core/spatial.hpp"
#include "data/robots.hpp"

namespace dynid::cli {

namespace po = boost::program_options;

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;
inline constexpr int kExitUsage = 2;
/// Ctrl-C stopped a long command (128 + SIGINT, what a shell reports for a process the signal
/// ended); its best result so far was written.
inline constexpr int kExitInterrupted = 130;

/// A mistake in the command line (exit code 2).
class UsageError : public Error {
 public:
  using Error::Error;
};

/// Parses the options of one command; prints help (-h, --help) or the version (--version) and
/// returns false then. Long options must be written in full (no abbreviations: "--meth" is an
/// unknown option, with the options it may mean suggested); -h is the only short option. Throws
/// UsageError (with the usage line) on unknown or malformed options. `positional` names options
/// that may be given without their flag, in order (-1 entries: the rest).
bool parseCommandLine(const std::vector<std::string>& args, const po::options_description& options,
                      const std::string& usage, po::variables_map& vm,
                      const po::positional_options_description* positional = nullptr);

/// One option of a command, as the help, the shell completion and the man pages show it.
struct OptionEntry {
  std::string name;       // long name, without "--"
  std::string parameter;  // "arg (=10)"; empty for a switch
  std::string help;       // with its range, as --help prints it
};
/// One command's options ("model export"), recorded by parseCommandLine in catalogue mode.
struct CommandOptions {
  std::string usage;
  std::vector<OptionEntry> options;
};
/// While `catalogue` is set, parseCommandLine appends the options it is given to it and returns
/// false without parsing (the command then returns without doing anything); nullptr ends it.
void setOptionCatalogue(std::vector<CommandOptions>* catalogue);

/// The build's version and commit: "0.2.0 (commit 1a2b3c4d5e6f)".
std::string versionText();

/// Begins the run its documents' provenance records (records/provenance.hpp): `arguments` (the
/// command line after "dynid"), this dynid's version and commit, the working directory.
void beginCommandRun(const std::vector<std::string>& arguments);

/// The value of --out for a command that writes a directory; "-" (standard output, one file) is
/// a usage error. Checks that the directory can be written before the work starts.
std::string outputDirectoryOption(const po::variables_map& vm);

/// "0,0.785,3.14" -> {0, 0.785, 3.14}; names the option and the entry at fault.
std::vector<double> parseList(const std::string& text, const std::string& option);
/// A list of exactly n entries, or one entry broadcast to n; names the option on mismatch.
Eigen::VectorXd parseJointVector(const std::string& text, const std::string& option, int n,
                                 bool allow_broadcast);
/// The joint vector of option `name` when given.
std::optional<Eigen::VectorXd> optionalJointVector(const po::variables_map& vm, const char* name,
                                                   int n, bool allow_broadcast);
/// The list of option `name` with exactly `count` entries; UsageError "--name takes `what`"
/// otherwise.
std::vector<double> fixedList(const po::variables_map& vm, const char* name, std::size_t count,
                              const char* what);
/// --link, --tool-xyz and --tool-rpy: where a body is attached (payload, model attach); `what`
/// names the body ("the payload", "the body").
void addAttachmentOptions(po::options_description& options, const std::string& what);
/// --tool-xyz and --tool-rpy as a pose in the link's frame (identity when neither is given).
Pose<double> attachmentFrameOption(const po::variables_map& vm);
/// Calls parse(text) and turns its InputError into a UsageError naming --option.
template <typename F>
auto parseOption(const po::variables_map& vm, const char* option, F parse) {
  try {
    return parse(vm[option].as<std::string>());
  } catch (const InputError& e) {
    throw UsageError(std::string("--") + option + ": " + e.what());
  }
}
// Every numeric option's range is checked when the command line is parsed, from the one table
// in core/option_ranges.hpp: read the value with vm[name].as<T>().
/// --threads: 0 (all cores) to 256 (core/option_ranges.hpp: more threads than cores only slow a run
/// down, and thousands exhaust the system's process table).
void addThreadsOption(po::options_description& options);
int threadsOption(const po::variables_map& vm);

/// A comma-separated list of names given to --`option` (empty when not given). Throws UsageError,
/// naming the option, for an empty name or one named twice.
std::vector<std::string> nameListOption(const po::variables_map& vm, const char* option);

/// How a ROS recording's sensor_msgs/JointState messages are read (prepare, monitor): --topic,
/// --stamp header|receive, --effort-topic.
void addRecordingOptions(po::options_description& options);
/// --stamp: true for receive (the recorder's time), false for header; UsageError otherwise.
bool receiveTimeOption(const po::variables_map& vm);
/// --joint-names as a list (empty when not given); UsageError for an empty or repeated name, or
/// a count other than `joints` (when > 0).
std::vector<std::string> jointNamesOption(const po::variables_map& vm, int joints);

/// The robot options (--drives, --drive-terms, --strict) as data/robots.hpp's RobotOptions.
/// Throws UsageError for --drives with --drive-terms or an unknown drive term.
RobotOptions robotOptions(const po::variables_map& vm);

/// The options every robot-using command takes: --robot, --drives, --drive-terms, --strict
/// (--robot required unless `required` is false).
void addRobotOptions(po::options_description& options, bool required = true);
/// Loads the robot named by --robot (warnings to stderr), a URDF's `fixed_joints` fixed at zero.
Model loadRobotFromOptions(const po::variables_map& vm,
                           const std::vector<std::string>& fixed_joints = {});
/// Loads another robot spec (--init, --truth, --prior) with the same --drives and --strict.
Model loadOtherRobot(const po::variables_map& vm, const char* option);

/// --samples, --seed, --tolerance of the structural analysis, and their values.
void addStructuralOptions(po::options_description& options);
StructuralOptions structuralOptions(const po::variables_map& vm);

/// --prior-weight (pc, and the searches that start from it; identify, study, demo) and its value
/// (physically_consistent.hpp: kDefaultPriorWeight, checkPriorWeight).
void addPriorWeightOption(po::options_description& options);
double priorWeightOption(const po::variables_map& vm);
/// --write-urdf's checks, before the work (identify, study): a URDF robot, a file (not -) that is
/// no input, in a directory that exists or is --out's (writeWriteBack makes that one). Returns the
/// URDF to write into (robot_spec). UsageError otherwise.
std::string writeUrdfSource(const po::variables_map& vm, const std::string& robot_spec);
/// --front, --front-weights, --front-tolerance (study, identify --method combined; the tolerance's
/// default is the requests' own, 0.05) and the weights (the default sweep with --front alone;
/// empty without either).
void addFrontOptions(po::options_description& options, const char* front_help);
std::vector<double> frontWeightsOption(const po::variables_map& vm);
/// --rest-velocity V[,V...] (identify, predict): each joint's rest velocity, one for all or one
/// per joint of `joints` (analysis/logs/rest.hpp; joints 0: the count is the library's to check);
/// empty when not given (measured on the data). UsageError for another count or a negative value.
void addRestVelocityOption(po::options_description& options);
std::vector<double> restVelocityOption(const po::variables_map& vm, int joints);
/// --torque-filter (identify, predict): `what` the filter is to the command, then its values.
void addTorqueFilterOption(po::options_description& options, const std::string& what);
/// --torque-filter's value: auto (std::nullopt), none (order 0) or CUTOFF[,ORDER]; UsageError
/// naming it otherwise.
TorqueFilterChoice torqueFilterOption(const po::variables_map& vm);
/// --keep-worse-refinements: report a refinement that ends above its search's training GC error
/// instead of keeping the search's result (analysis/estimation/pipeline.hpp,
/// RefineSettings::keep_if_better).
void addKeepRefinementOption(po::options_description& options);
bool keepIfBetterOption(const po::variables_map& vm);

/// An option given on the command line (not a default).
bool given(const po::variables_map& vm, const char* option);

/// `word` as one shell word: as it is when it holds only safe characters, else in single quotes
/// (a command line a user can paste, whatever the file names hold).
std::string shellWord(const std::string& word);
/// Throws UsageError when any of `options` is given while `used` is false: an option the chosen
/// method or mode would ignore ("--population applies to --method ga and hybrid, not nlo").
void refuseUnused(const po::variables_map& vm, bool used,
                  std::initializer_list<const char*> options, const std::string& applies);

/// This executable's path (/proc/self/exe), to start it again: batch's workers, a rerun. Throws
/// InputError when it cannot be found.
std::string selfExecutable();

/// Whether standard error is a terminal (progress lines go there only then).
bool stderrIsTerminal();

/// For its lifetime, SIGINT sets flag() instead of ending the process (the run then stops
/// cleanly, writing its best result); the previous handler comes back on destruction.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  const std::atomic<bool>* flag() const;
  /// Whether SIGINT came while it was held.
  bool interrupted() const;

 private:
  void (*previous_)(int);
};

/// The exit code of a command that held `guard` and has written its outputs: kExitInterrupted,
/// with "dynid <command>: interrupted (Ctrl-C): <written>" on standard error, when SIGINT stopped
/// it; kExitOk otherwise.
int exitAfter(const InterruptGuard& guard, const std::string& command, const std::string& written);

}  // namespace dynid::cli
