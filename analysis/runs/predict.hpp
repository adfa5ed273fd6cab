// The runs wing's room for dynid predict: an estimate (or a robot's own parameters) applied to a
// dataset, streamed, with its band and the raw torques. Nothing here prints or writes a report.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "analysis/estimation/reversals.hpp"
#include "analysis/estimation/streaming.hpp"
#include "analysis/estimation/training_rows.hpp"
#include "analysis/logs/rest.hpp"
#include "analysis/records/model_source.hpp"
#include "core/model.hpp"
#include "core/parallel.hpp"

namespace dynid {

// ---- applying an estimate to data ----

struct PredictRequest {
  std::string estimate_file;  // an identify estimate.json (empty: `model`)
  std::string data_file;      // a dataset CSV
  std::string robot_spec;     // empty: the estimate's own; with `model`, its spec
  /// Without an estimate: this robot with its own parameters (a URDF, a written-back model, a
  /// built-in), which has no covariance and so no band.
  std::optional<Model> model;
  int threads = kAllThreads;       // 0: all cores; the same result for any count
  PredictionSink* sink = nullptr;  // receives every sample's prediction, in order (may be null)
  /// prepare --keep-raw-torque's validate_raw.csv for data_file: the raw torques at the log's
  /// stamps, compared against too (empty: none).
  std::string raw_file = "";
  /// The joints' rest velocities (analysis/logs/rest.hpp): one for all or one per joint; empty:
  /// measured on data_file, as identify measures its training data.
  std::vector<double> rest_velocity = {};
  /// The low-pass data_file's torque went through (analysis/estimation/training_rows.hpp):
  /// std::nullopt, the prepare.json beside data_file's; order 0, none. With one, the prediction
  /// compared with the filtered torque (statistics, band coverage) has its friction that needs
  /// sign(dq) through the same filter, as identify's held-out error does, and the note on
  /// reversals counts the rows a fit would take; the sink still gets the model's own torque.
  TorqueFilterChoice torque_filter = std::nullopt;
};
struct PredictOutcome {
  Model model;  // the robot with the estimate's standard parameters
  std::string robot_spec, method;
  ModelSource source;  // where the robot came from (prediction.json embeds it with the model)
  Prediction prediction;
  std::optional<PredictionBand> band;  // the estimate's 95 % band (absent in older estimates)
  std::optional<Validation> raw;       // against the raw torques (raw_file), when given
  ReversalResidual reversals;          // where the residual lies in velocity (reversals.hpp)
  std::string raw_file;
  int raw_skipped = 0;             // raw samples no two adjacent dataset samples bracket
  std::vector<RestVelocity> rest;  // each joint's rest velocity on data_file (or given)
  /// The filter reproduced (inactive: none), where it came from or why there is none, and its
  /// reach [samples] (0: nothing reproduced).
  TorqueFilter torque_filter;
  std::string torque_filter_source;
  int filter_reach = 0;
  std::vector<std::string> warnings;  // an estimate of an earlier version read as it is
};
/// The torque filter a prediction reproduces, where it came from (or why there is none), its reach
/// [samples] and the rows it gives (set only when it is active and the model has friction that
/// needs sign(dq)).
struct PredictionFilter {
  TorqueFilter filter;
  std::string source;
  int reach = 0;
  std::optional<FitRows> rows;
};
/// `choice`, else the prepare.json beside data_file (data in memory, `data`: none unless given),
/// with `model`'s rest velocities set. Throws InputError naming the data when the filter's cutoff
/// is not below half its rate.
PredictionFilter predictionFilter(const Model& model, const std::string& data_file,
                                  const Trajectory* data, const TorqueFilterChoice& choice);

/// Loads the robot the estimate names (or `robot_spec`) with the estimate's drive terms, sets its
/// standard parameters and predicts, streaming the dataset. Throws ParseError for a malformed
/// estimate, InputError when the estimate does not fit the robot (another robot, another drive
/// model: the parameter named), and InputError naming data_file when a given filter's cutoff is
/// not below half its rate.
PredictOutcome predictRun(const PredictRequest& request);

}  // namespace dynid
