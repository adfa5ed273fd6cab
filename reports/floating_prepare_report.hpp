// A floating robot's prepared recording: floating_prepare.json (what each topic held, the rate,
// the filter and why, the runs kept) and the console lines (`dynid prepare --floating-base`).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/floating/prepare.hpp"

namespace dynid {

nlohmann::json floatingPrepareJson(const FloatingModel& model, const std::string& recording,
                                   const FloatingPrepareOutcome& outcome);
/// One line per topic, the time base and filter, then the files written.
std::string floatingPrepareSummary(const FloatingModel& model,
                                   const FloatingPrepareOutcome& outcome,
                                   const std::string& dataset, const std::string& document);

}  // namespace dynid
