#include "reports/batch_report.hpp"

#include <sstream>

#include "analysis/records/document.hpp"
#include "data/json_number.hpp"
#include "reports/output.hpp"

namespace dynid {

using nlohmann::json;

namespace {
json rowOf(const RunRecord& run) {
  const auto& [name, result] = run;
  json row = {{"run", name}};
  for (const std::string& c : batchSpecColumns()) row[c] = result.spec[c];
  for (const std::string& m : batchMetricColumns()) row[m] = result.metrics[m];
  return row;
}
}  // namespace

std::string batchResultsJson(const BatchOutcome& outcome) {
  json rows = json::array();
  for (const RunRecord& run : outcome.done) rows.push_back(rowOf(run));
  const json table = {{"schema_version", kBatchResultsDocument.schema_version},
                      {"kind", kBatchResultsDocument.kind},
                      {"runs_total", outcome.total},
                      {"runs_done", outcome.done.size()},
                      {"missing", outcome.missing},
                      {"plan", outcome.plan},
                      {"rows", rows}};
  return jsonText(table, 1) + "\n";
}

std::string batchResultsCsv(const BatchOutcome& outcome) {
  std::ostringstream csv;
  csv << "run";
  for (const std::string& c : batchSpecColumns()) csv << "," << c;
  for (const std::string& m : batchMetricColumns()) csv << "," << m;
  csv << "\n";
  for (const auto& [name, result] : outcome.done) {
    csv << name;
    for (const std::string& c : batchSpecColumns()) {
      const json& v = result.spec[c];
      csv << "," << (v.is_string() ? v.get<std::string>() : jsonText(v));
    }
    for (const std::string& m : batchMetricColumns()) {
      const json& v = result.metrics[m];
      csv << "," << (v.is_null() ? "" : jsonText(v));
    }
    csv << "\n";
  }
  return csv.str();
}

std::string batchRunDocument(const BatchRunRecord& record) {
  return jsonText(batchRunJson(record), 1) + "\n";
}

void writeBatchTables(const std::string& dir, const BatchOutcome& outcome) {
  writeReportFiles(dir, {{"results.json", batchResultsJson(outcome)},
                         {"results.csv", batchResultsCsv(outcome)}});
}

}  // namespace dynid
