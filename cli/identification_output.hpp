// JSON and Markdown for dynid identifiability / identify (moves to reports/ with the analysis
// issue).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "cli/common.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares.hpp"
#include "identifiability/observation.hpp"

namespace dynid::cli {

inline constexpr int kIdentificationSchemaVersion = 1;

/// --samples, --seed, --tolerance for the structural analysis on random states.
void addStructuralOptions(po::options_description& options);
/// Base parameters from seeded random states (the structural rank).
BaseParameters structuralBaseParameters(const Model& model, const po::variables_map& vm);

nlohmann::json identifiabilityJson(const Model& model, const BaseParameters& base,
                                   const po::variables_map& vm);
nlohmann::json excitationJson(const BaseParameters& base, const Observation& observation,
                              const std::string& file);
std::string identifiabilityMarkdown(const nlohmann::json& report);

nlohmann::json estimateJson(const Model& model, const BaseParameters& base,
                            const BaseEstimate& estimate, const std::string& data_file);
nlohmann::json validationJson(const Validation& validation, const std::string& file);
std::string estimateMarkdown(const nlohmann::json& report);

/// 4 significant digits ("3.2e+11", "inf").
std::string formatShort(double x);

}  // namespace dynid::cli
