// The documents of `dynid batch`: results.json and results.csv (one row per finished run: the
// spec's columns, then the metrics), and a worker's run record.
#pragma once

#include <string>
#include <vector>

#include "analysis/studies/batch.hpp"

namespace dynid {

/// results.json: schema_version 1, kind dynid.batch.results, runs_total, runs_done, missing,
/// plan (the manifest, --quick, shard, shards: what `batch merge` checks), rows.
std::string batchResultsJson(const BatchOutcome& outcome);
/// results.csv: run, the spec's columns, the metrics (an empty cell for a null metric).
std::string batchResultsCsv(const BatchOutcome& outcome);
/// A run record as its file holds it.
std::string batchRunDocument(const BatchRunRecord& record);

/// Writes results.json and results.csv into `dir`.
void writeBatchTables(const std::string& dir, const BatchOutcome& outcome);

}  // namespace dynid
