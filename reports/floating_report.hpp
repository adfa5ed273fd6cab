// A floating-base robot's documents: floating_identifiability.json, its Markdown report and the
// console line (`dynid identifiability --floating-base`).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/floating/identifiability.hpp"
#include "analysis/floating/simulate.hpp"

namespace dynid {

/// A contact as the floating documents write it: name, kind (point or frame), body.
nlohmann::json floatingContactJson(const Contact& contact);

nlohmann::json floatingIdentifiabilityJson(const FloatingModel& model,
                                           const FloatingIdentifiabilityOutcome& outcome);
std::string floatingIdentifiabilityMarkdown(const FloatingModel& model,
                                            const FloatingIdentifiabilityOutcome& outcome);
/// One line per sensor set, then the files written.
std::string floatingIdentifiabilitySummary(const FloatingModel& model,
                                           const FloatingIdentifiabilityOutcome& outcome,
                                           const std::string& dir);

/// `dynid simulate --floating-base`'s console lines: what was simulated (random states, a design,
/// or the motion of `motion_file`) to `out` ("-": standard output), how many states the cones
/// left out of `drawn`, and the soles.
std::string floatingSimulationSummary(const FloatingModel& model,
                                      const FloatingSimulationOptions& options,
                                      const FloatingDataset& dataset, int drawn,
                                      const std::string& motion_file, const std::string& out);

}  // namespace dynid
