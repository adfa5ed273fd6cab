// What `dynid model` and `dynid dynamics` print, and `dynid model export`'s and `dynid
// simulate`'s documents.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/records/model_source.hpp"
#include "analysis/runs/arm.hpp"
#include "analysis/runs/simulate.hpp"

namespace dynid {

/// Kinematics, limits and parameters (standard and paper form) as a table.
std::string modelShowText(const Model& model);
/// One line per violation, or "all n links are physically consistent".
std::string modelCheckText(const Model& model, const std::vector<ConsistencyViolation>& violations);
/// {schema_version 1, robot, consistent, violations[{link, link_name, condition, detail}]}.
nlohmann::json modelCheckJson(const Model& model,
                              const std::vector<ConsistencyViolation>& violations);
/// The model as a file of `format`: "urdf", "json" (dynid's) or "mjcf" (MuJoCo). Throws
/// InputError for another format.
std::string modelDocument(const Model& model, const std::string& format);
/// Embeds the robot a document used: "model" (dynid JSON, with its parameters: loadable from the
/// document alone) and "model_source" (where it came from).
void embedModel(nlohmann::json& document, const Model& model, const ModelSource& source);
/// What `modelDocument(model, format)` leaves out, one sentence each (none for "json").
std::vector<std::string> modelExportNotes(const Model& model, const std::string& format);

/// {schema_version 1, robot, drives, q, dq, tau, M, ddq}.
nlohmann::json dynamicsJson(const Model& model, const DynamicsOutcome& outcome);
/// q, dq, ddq, tau and M(q) with units.
std::string dynamicsText(const Model& model, const DynamicsOutcome& outcome);

/// "wrote FILE: robot, N samples x n joints, t = 0..T s, tracking error RMS ..., peak |tau| ...".
std::string simulateSummary(const Model& model, const SimulateOutcome& outcome,
                            const std::string& file);

}  // namespace dynid
