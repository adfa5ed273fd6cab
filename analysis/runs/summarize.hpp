// The runs wing's room for dynid summarize: least-squares summaries of logs (one per log, memory
// independent of its length, identifiability/least_squares_summary.hpp), their merge, and the
// base parameters a summary is of. identify estimates from one (its request's `summary`,
// identify.hpp).
#pragma once

#include <string>
#include <vector>

#include "analysis/estimation/training_rows.hpp"
#include "analysis/records/summary_record.hpp"
#include "core/model.hpp"
#include "core/parallel.hpp"
#include "core/run_control.hpp"
#include "core/trajectory.hpp"
#include "identifiability/base_parameters.hpp"

namespace dynid {

struct SummarizeRequest {
  Model model;             // the robot with its drive terms (parameters: the prior of the unseen)
  std::string robot_spec;  // how it was named, recorded as the summary's model_source
  std::vector<std::string> data_files;  // one summary each, in order
  /// Data in memory instead of the files (the Python module's arrays; not owned): one summary,
  /// named `data_name`.
  const Trajectory* data = nullptr;
  std::string data_name = "data";
  /// Each log's rest velocities: one for all, or one per joint; empty: measured on each log.
  std::vector<double> rest_velocity;
  /// Each log's torque filter: std::nullopt, the prepare.json beside it says (as identify).
  TorqueFilterChoice torque_filter;
  StructuralOptions structural;
  int threads = 0;  // 0: every core; the same result for any count
  RunControl control;

  /// Throws InputError naming the first bad field (`data` when there is none to summarize).
  void check() const;
};

struct SummarizeOutcome {
  std::vector<Summary> summaries;  // one per log summarized, in order
  /// Stopped (control) before every log was read: `summaries` holds the logs read whole, the
  /// log being read is dropped.
  bool interrupted = false;
};
/// One summary per log (data_files in order, or the data in memory). Throws what identify throws
/// for a dataset (ParseError naming the file, line and column; InputError naming it for another
/// joint count or a filter above the data's rate).
SummarizeOutcome summarizeRun(const SummarizeRequest& request);

/// The summaries after one another, as one: their logs' rows together. Throws InputError naming
/// the first summary (`names`, in order) whose robot's kinematics, drive terms, base parameters or
/// structural options differ from the first's, or for none at all.
Summary mergeSummaries(const std::vector<const Summary*>& summaries,
                       const std::vector<std::string>& names);

/// The base parameters of the summary's robot (its structure and structural options). Throws
/// InputError when they are not those its factors were made with (another version of dynid chose
/// otherwise).
BaseParameters summaryBase(const Summary& summary, const std::string& name);

}  // namespace dynid
