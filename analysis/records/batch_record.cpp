#include "analysis/records/batch_record.hpp"

#include <filesystem>

#include "analysis/records/document.hpp"
#include "core/errors.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"

namespace dynid {

using nlohmann::json;

json batchRunJson(const BatchRunRecord& record) {
  return {{"schema_version", kBatchRunDocument.schema_version},
          {"kind", kBatchRunDocument.kind},
          {"spec", record.spec},
          {"metrics", record.metrics}};
}

std::optional<BatchRunRecord> storedBatchRun(const std::string& path, const json& spec) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  try {
    const json r = json::parse(readFile(path));
    if (r.value("kind", "") == kBatchRunDocument.kind && r["spec"] == spec &&
        r["metrics"].is_object())
      return BatchRunRecord{r["spec"], r["metrics"]};
  } catch (const std::exception&) {
    // Unreadable or partial: the run is to be done again.
  }
  return std::nullopt;
}

std::map<std::string, BatchRunRecord> readBatchRuns(const std::string& dir) {
  std::map<std::string, BatchRunRecord> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir + "/runs", ec)) {
    if (entry.path().extension() != ".json") continue;  // a killed worker's *.tmp.<pid>
    const std::string file = entry.path().string();
    const json r = parseJson(readFile(file), file);
    const JsonReader read(file);
    read.header(r, kBatchRunDocument.schema_version, kBatchRunDocument.kind);
    read.onlyKeys(r, "", {"schema_version", "kind", "spec", "metrics"});
    out[entry.path().stem().string()] = {read.object(read.field(r, "", "spec"), "spec"),
                                         read.object(read.field(r, "", "metrics"), "metrics")};
  }
  if (ec) throw ParseError(dir + "/runs", 0, "", ec.message());
  return out;
}

json BatchPlanRecord::json() const {
  return {{"manifest", manifest}, {"quick", quick}, {"shard", shard}, {"shards", shards}};
}

BatchPlanRecord readBatchPlan(const std::string& file) {
  const nlohmann::json table = parseJson(readFile(file), file);
  const JsonReader read(file);
  read.header(table, kBatchResultsDocument.schema_version, kBatchResultsDocument.kind);
  const nlohmann::json& plan = read.field(table, "", "plan");
  read.onlyKeys(plan, "plan", {"manifest", "quick", "shard", "shards"});
  BatchPlanRecord out;
  out.manifest = read.object(read.field(plan, "plan", "manifest"), "plan.manifest");
  out.quick = read.boolean(plan, "plan", "quick");
  out.shards = read.integer(plan, "plan", "shards", 1, 1000000);
  out.shard = read.integer(plan, "plan", "shard", 1, out.shards);
  return out;
}

}  // namespace dynid
