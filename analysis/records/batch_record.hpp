// dynid batch's documents: a run record (runs/<name>.json: the run's spec and its comparison row)
// and the plan in results.json, written by analysis/batch and reports/batch_report and read back
// here when a batch resumes or shards merge.
#pragma once

#include <map>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace dynid {

/// One finished run: its spec (a manifest row, every key) and its metrics (a comparison row,
/// analysis/studies/comparison.hpp's metricsJson).
struct BatchRunRecord {
  nlohmann::json spec, metrics;
};
/// The run record document (kBatchRunDocument).
nlohmann::json batchRunJson(const BatchRunRecord& record);
/// The record stored at `path` when it is a complete run record of exactly `spec`; std::nullopt
/// otherwise (missing, unreadable, another spec: the run is to be done).
std::optional<BatchRunRecord> storedBatchRun(const std::string& path, const nlohmann::json& spec);
/// Every run record under dir/runs, strictly, by name (the file's stem). A file that is not a run
/// record is a ParseError naming it (a merge must not drop a run silently).
std::map<std::string, BatchRunRecord> readBatchRuns(const std::string& dir);

/// results.json's plan: the manifest and settings a shard ran.
struct BatchPlanRecord {
  nlohmann::json manifest;
  bool quick = false;
  long long shard = 1, shards = 1;
  nlohmann::json json() const;
};
/// The plan of the results.json at `file`, strictly (kBatchResultsDocument). Throws ParseError
/// naming the file and the field.
BatchPlanRecord readBatchPlan(const std::string& file);

}  // namespace dynid
