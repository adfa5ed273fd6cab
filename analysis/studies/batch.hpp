// Batch studies (`dynid batch`, docs/BATCH.md): a manifest's grid of Study runs, resumable from
// the results already stored, shardable across machines, with shards merged afterwards. The
// worker processes that run them are the CLI's (cli/batch_workers.hpp). The tables are written by
// reports/batch_report.hpp.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/records/batch_record.hpp"
#include "analysis/studies/study.hpp"

namespace dynid {

/// The most runs one manifest may describe: 1e5 study runs are about a day on a 32-core node, and
/// their expanded specs take about 150 MB (1e6 would take 1.5 GB before the first run starts).
inline constexpr double kMaxBatchRuns = 1e5;

/// The keys a run's spec has, with their defaults (StudySettings; "method" has none).
const nlohmann::json& batchSpecDefaults();
/// The results table's columns: the spec's (method, then the settings), then the metrics.
const std::vector<std::string>& batchSpecColumns();
const std::vector<std::string>& batchMetricColumns();

/// Every run of a manifest, in grid order (keys sorted, the last varying fastest). Files named in
/// the manifest (a `trajectory`, a `robot` ending in .urdf or .json) are relative to the
/// manifest's directory (readManifest). Throws ParseError naming the file and the key or grid
/// entry at fault: an unknown key, a value of the wrong type or out of its integer range, an
/// unknown method, a robot that does not load.
std::vector<nlohmann::json> expandManifest(const std::string& file);
/// The manifest file parsed, with the relative file paths of `trajectory` and of a `robot` ending
/// in .urdf or .json (in `fixed` and in `grid`) made relative to the current directory by
/// prefixing the manifest's directory: a manifest runs the same from any working directory.
nlohmann::json readManifest(const std::string& file);
/// The same for a manifest already parsed; `file` names it in errors.
std::vector<nlohmann::json> expandManifest(const nlohmann::json& manifest, const std::string& file);
/// A run's StudySettings (threads 1: batch parallelism is across runs).
StudySettings studySettingsOf(const nlohmann::json& spec);
/// "000012-<16 hex digits of the spec's hash>": the run's identity and file stem.
std::string batchRunName(std::size_t index, const nlohmann::json& spec);

/// A finished run by name (its record: analysis/records/batch_record.hpp).
using RunRecord = std::pair<std::string, BatchRunRecord>;  // (name, record)

/// Runs one spec in this process (a worker's job): its Study and method, measured.
BatchRunRecord runBatchSpec(const nlohmann::json& spec);

struct BatchPlan {
  std::string manifest, dir;
  std::vector<nlohmann::json> runs;  // the whole grid
  std::vector<std::size_t> mine;     // this shard's runs
  std::vector<std::size_t> todo;     // this shard's runs without a valid stored result
  nlohmann::json record;  // {manifest, quick, shard, shards}: results.json's "plan", for merging
  std::string path(std::size_t i) const;  // dir/runs/<name>.json
};
/// What `quick` gives every run ("4 s of data, 10 segments, ..."): the help text says it from here.
std::string batchQuickDescription();
/// Expands the manifest, applies --quick, validates every run before anything starts (naming the
/// run and field), and finds what is already done. `shard` is 1-based, 1 <= shard <= shards.
BatchPlan planBatch(const std::string& manifest, const std::string& dir, bool quick, int shard,
                    int shards);

struct BatchOutcome {
  std::vector<RunRecord> done;       // this shard's stored results, in index order
  std::vector<std::string> missing;  // this shard's runs without one
  std::vector<std::string> failed;   // runs whose worker failed (not when interrupted)
  std::size_t total = 0;             // runs in the whole grid
  nlohmann::json plan;               // the BatchPlan's record (merged: shard 1 of 1)
  bool interrupted = false;
};
/// This shard's stored results (plan.mine): done in index order, and the missing runs named. The
/// worker processes that run plan.todo belong to the front end (cli/batch_workers.hpp); a run
/// is one `runBatchSpec` whose record is stored at plan.path(i).
BatchOutcome collectBatch(const BatchPlan& plan);

/// Every run stored under the shard directories, checked against the grid their results.json's
/// plan describes (the manifest itself, --quick and the shard count, equal in every shard).
/// Throws ParseError naming the file for a corrupt or foreign results.json or run record (a run
/// whose spec is not its grid entry's), and InputError naming the missing runs and
/// the shards not given when the merge is incomplete, unless `allow_missing`.
BatchOutcome mergeBatches(const std::vector<std::string>& dirs, bool allow_missing = false);

}  // namespace dynid
