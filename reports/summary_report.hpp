// summary.json (dynid summarize, the Python module's Summary.to_json): a least-squares summary of
// one robot's logs, read back by analysis/records/summary_record.hpp.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/records/summary_record.hpp"

namespace dynid {

/// One log of a summary: its file, sha256, samples, rest velocities and torque filter (as a
/// summary's `sources` hold it; fleet.json's robots too).
nlohmann::json summarySourceJson(const SummarySource& source);

/// The document, without provenance (its writers stamp it). With `detached`, the batches' values
/// are appended there instead, each batch's "factors" "" (a binary form: the Python module's
/// pickles; summaryFrom reads it back given the same values).
nlohmann::json summaryJson(const Summary& summary, std::vector<double>* detached = nullptr);

/// Writes each (file name, summary) into `dir` as one set (all or none, reports/output.hpp), each
/// stamped with the run's provenance. Returns the console lines: per file its logs, samples,
/// batches and size.
std::string writeSummaries(const std::string& dir,
                           const std::vector<std::pair<std::string, Summary>>& named);

}  // namespace dynid
