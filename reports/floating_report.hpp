// A floating-base robot's documents: floating_identifiability.json, its Markdown report and the
// console line (`dynid identifiability --floating-base`).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/floating/identifiability.hpp"

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

}  // namespace dynid
