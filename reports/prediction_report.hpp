// What `dynid predict` writes: predicted.csv (time, measured and predicted torque per joint),
// prediction.json (relative error overall and per joint, RMS per joint) and torques.svg (measured
// against predicted torque for every joint, the figure every identification paper shows).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/runs/predict.hpp"

namespace dynid {

nlohmann::json predictionJson(const PredictOutcome& outcome, const std::string& estimate_file,
                              const std::string& data_file);

/// A 95 % band whose coverage of a joint's samples is outside [low, high] is reported as a
/// warning: the band does not describe these data.
inline constexpr double kBandCoverageLow = 0.90, kBandCoverageHigh = 0.99;
/// The warnings for the joints whose coverage is outside those bounds (empty when none).
std::vector<std::string> bandWarnings(const Eigen::VectorXd& coverage);

/// A prediction against the raw held-out torques (prepare --keep-raw-torque), as JSON and as
/// one console line; `skipped`: raw samples no two adjacent dataset samples bracket.
nlohmann::json rawValidationJson(const Validation& raw, const std::string& file, int skipped);
/// estimate.json's and prediction.json's `reversals`: the band, the shares and the flagged joints
/// (1-based) of analysis/estimation/reversals.hpp.
nlohmann::json reversalsJson(const ReversalResidual& r);
/// When some joints' residual gathers near zero velocity (ReversalResidual::flagged): "friction
/// at reversals: ..." naming them with their shares, and what the drive terms can do about it
/// (add fc; add fs, Stribeck; or nothing more: stick is beyond them). "" when none is flagged.
/// `filtering`, when given, is said after it: whether the torque's low-pass can have made it.
std::string reversalNote(DriveTerms terms, const ReversalResidual& r,
                         const std::string& filtering = "");
/// The note for joints whose residual has friction's shape (ReversalResidual::friction_flagged)
/// while the drive terms lack fv, fc or fo: the joints and the --drive-terms that adds the
/// missing ones ("" when none is flagged or none is missing). reversalNote gives it first.
/// `residual` names the residual measured.
std::string missingFrictionNote(DriveTerms terms, const ReversalResidual& r,
                                const std::string& residual = "the torque residual");
std::string rawValidationLine(const Validation& raw, int skipped);

/// estimate.json's and prediction.json's `rest_velocity`: per joint the velocity within which it
/// is at rest, the two levels it is the larger of, how it was found, and its samples at rest.
nlohmann::json restVelocityJson(const std::vector<RestVelocity>& rest);
/// prediction.json's and estimate.json validation's `at_rest` (RestPrediction, per joint).
nlohmann::json atRestJson(const RestPrediction& rest);
/// "at rest (|dq| within the rest velocity): ..." for the joints with samples at rest: their
/// residual's spread against the measured torque's and the static friction band; "" when none.
std::string atRestLine(const RestPrediction& rest);
/// "rest velocity per joint [rad/s]: ... (from the chatter at zero on joints 1, 2); samples at
/// rest: ...": the identify and predict console and report line.
std::string restVelocityLine(const std::vector<RestVelocity>& rest);

/// Measured against predicted torque, one panel per joint, as an SVG; nullopt without gnuplot.
std::optional<std::string> torqueFigure(const Prediction& prediction, const std::string& title);

/// The residuals tau - tau_hat per joint against time: the training data's, and the held-out
/// data's in another colour when given. nullopt without gnuplot.
std::optional<std::string> residualFigure(const Prediction& train, const Prediction* validate);
/// Per joint, the histogram of the training residuals as a density over +-4 RMS, with the normal
/// density of the same RMS: a bias, heavy tails or two modes (unmodelled friction) show. nullopt
/// without gnuplot.
std::optional<std::string> residualHistogram(const Prediction& train);

class AtomicWriter;
class OutputSet;

/// predicted.csv (t, tau1..taun, tau_hat1..tau_hatn, and band1..bandn, the 95 % band's half widths,
/// when the estimate has a band), written sample by sample as the prediction
/// streams (memory independent of the data's length) into a temporary of the output set that
/// writePrediction publishes; nothing is left when the run fails or is interrupted (a directory
/// it created is removed again).
class PredictedCsv : public PredictionSink {
 public:
  /// Creates `dir` when the first samples arrive. Throws Error when it cannot be written.
  explicit PredictedCsv(const std::string& dir);
  ~PredictedCsv() override;
  void samples(const Eigen::VectorXd& time, const Eigen::MatrixXd& measured,
               const Eigen::MatrixXd& predicted) override;
  void bands(const Eigen::MatrixXd& half_width) override;
  /// predicted.csv whole (the header alone without samples), and the set it belongs to, to be
  /// published with the other files.
  OutputSet& finish();

 private:
  void open();  // on the first samples: the directory and the temporary
  std::string dir_;
  std::unique_ptr<OutputSet> set_;
  AtomicWriter* out_ = nullptr;
  bool created_dir_ = false;
  bool header_written_ = false;
  bool with_band_ = false;
  const Eigen::MatrixXd* band_ = nullptr;  // the next chunk's half widths
  std::string row_;
};

/// Writes prediction.json and the figure into `dir` (the figure only when gnuplot works; a
/// warning line is then part of the summary) and commits `csv`. Returns the console summary.
std::string writePrediction(const std::string& dir, const PredictOutcome& outcome,
                            const std::string& estimate_file, const std::string& data_file,
                            PredictedCsv& csv);

}  // namespace dynid
