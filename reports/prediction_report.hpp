// What `dynid predict` writes: predicted.csv (time, measured and predicted torque per joint),
// prediction.json (relative error overall and per joint, RMS per joint) and torques.svg (measured
// against predicted torque for every joint, the figure every identification paper shows).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/runs.hpp"

namespace dynid {

inline constexpr int kPredictionSchemaVersion = 1;

nlohmann::json predictionJson(const PredictOutcome& outcome, const std::string& estimate_file,
                              const std::string& data_file);

/// Measured against predicted torque, one panel per joint, as an SVG; nullopt without gnuplot.
std::optional<std::string> torqueFigure(const Prediction& prediction, const std::string& title);

/// The residuals tau - tau_hat per joint against time: the training data's, and the held-out
/// data's in another colour when given. nullopt without gnuplot.
std::optional<std::string> residualFigure(const Prediction& train, const Prediction* validate);
/// Per joint, the histogram of the training residuals as a density over +-4 RMS, with the normal
/// density of the same RMS: a bias, heavy tails or two modes (unmodelled friction) show. nullopt
/// without gnuplot.
std::optional<std::string> residualHistogram(const Prediction& train);

/// Writes the three files into `dir` (the figure only when gnuplot works; a warning line is then
/// part of the summary). Returns the console summary.
std::string writePrediction(const std::string& dir, const PredictOutcome& outcome,
                            const std::string& estimate_file, const std::string& data_file);

}  // namespace dynid
