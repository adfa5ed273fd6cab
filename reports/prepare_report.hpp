// What `dynid prepare` writes: the dataset CSV(s) and prepare.json (what was done, rates, jitter,
// gaps, runs, the filter, the torque noise), and its console summary.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "analysis/logs/prepare.hpp"
#include "core/parallel.hpp"

namespace dynid {

nlohmann::json prepareJson(const LogSource& source, const PrepareOptions& options,
                           const PrepareOutcome& outcome);

/// q's and tau's spectra (log-log) with the trajectory band and the cutoff marked; nullopt
/// without spectra or gnuplot.
std::optional<std::string> spectrumFigure(const PrepareOutcome& outcome);
/// The noisiest joint's torque over the outcome's excerpt, before and after the filter; nullopt
/// without a filter or gnuplot.
std::optional<std::string> filteredFigure(const PrepareOutcome& outcome);

/// Writes train.csv, validate.csv (when there is a validation part), prepare.json, spectrum.svg
/// and filtered.svg (when gnuplot runs) into `dir`, each atomically. Returns the console summary.
/// The datasets' rows are formatted on `threads` threads (kAllThreads: every hardware thread; the
/// same bytes for any count).
std::string writePrepared(const std::string& dir, const LogSource& source,
                          const PrepareOptions& options, const PrepareOutcome& outcome,
                          int threads = kAllThreads);

}  // namespace dynid
