// A floating-base robot's estimate: floating_identification.json, its Markdown report and the
// console lines (`dynid identify --floating-base`).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/floating/identify.hpp"
#include "analysis/floating/payload.hpp"

namespace dynid {

/// Where the data came from, and the payload estimated on them (empty: none asked), for the
/// documents.
struct FloatingDataSources {
  std::string data, validation;           // files (validation empty: none)
  std::vector<FloatingPayload> payloads;  // one per set (FloatingIdentifyOutcome::sets' order)
  /// The unloaded robot's dataset the payloads come from (floatingPayloadsFromPair); empty: from
  /// the robot's parameters (floatingPayloads).
  std::string unloaded;
};

nlohmann::json floatingIdentificationJson(const FloatingModel& model,
                                          const FloatingIdentifyOutcome& outcome,
                                          const FloatingDataSources& sources);
std::string floatingIdentificationMarkdown(const FloatingModel& model,
                                           const FloatingIdentifyOutcome& outcome,
                                           const FloatingDataSources& sources);
/// One line per sensor set (its estimate's measures, or why it has none), then the files written.
std::string floatingIdentificationSummary(const FloatingModel& model,
                                          const FloatingIdentifyOutcome& outcome,
                                          const FloatingDataSources& sources,
                                          const std::string& dir);

}  // namespace dynid
