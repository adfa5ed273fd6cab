#include "analysis/records/summary_record.hpp"

#include <limits>

#include "analysis/records/document.hpp"
#include "analysis/records/provenance.hpp"
#include "core/errors.hpp"
#include "data/digest/base64.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"
#include "data/model_json.hpp"

namespace dynid {

namespace {

using json = nlohmann::json;

std::vector<double> doubles(const JsonReader& read, const json& value, const std::string& path,
                            double lo) {
  const Eigen::VectorXd v = read.vector(value, path);
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (v[i] < lo)
      read.fail(JsonReader::index(path, static_cast<std::size_t>(i)),
                "below " + std::to_string(lo));
  return {v.data(), v.data() + v.size()};
}

SummarySource sourceFrom(const JsonReader& read, const json& value, const std::string& path,
                         int joints) {
  read.object(value, path);
  read.onlyKeys(
      value, path,
      {"file", "sha256", "samples", "rest_velocity", "torque_filter", "torque_filter_source"});
  SummarySource out;
  out.file = read.string(value, path, "file");
  out.sha256 = read.string(value, path, "sha256");
  out.samples = read.integer(value, path, "samples", 0, std::numeric_limits<int>::max());
  out.rest_velocity = doubles(read, read.field(value, path, "rest_velocity"),
                              JsonReader::join(path, "rest_velocity"), 0.0);
  if (static_cast<int>(out.rest_velocity.size()) != joints)
    read.fail(JsonReader::join(path, "rest_velocity"),
              "expected one per joint (" + std::to_string(joints) + ")");
  const json& filter = read.field(value, path, "torque_filter");
  if (!filter.is_null()) {
    const std::string at = JsonReader::join(path, "torque_filter");
    read.object(filter, at);
    read.onlyKeys(filter, at, {"order", "cutoff_hz", "rate_hz"});
    out.torque_filter.order = static_cast<int>(read.integer(filter, at, "order", 1, 16));
    out.torque_filter.rate = read.number(filter, at, "rate_hz", 1e-9);
    out.torque_filter.cutoff =
        read.number(filter, at, "cutoff_hz", 1e-9, 0.5 * out.torque_filter.rate);
  }
  out.torque_filter_source = read.string(value, path, "torque_filter_source");
  return out;
}

std::vector<std::vector<int>> supportFrom(const JsonReader& read, const json& value, int joints,
                                          int num_base) {
  const json& list = read.array(value, "least_squares.support");
  if (static_cast<int>(list.size()) != joints)
    read.fail("least_squares.support",
              "expected one list per joint (" + std::to_string(joints) + ")");
  std::vector<std::vector<int>> out;
  for (std::size_t j = 0; j < list.size(); ++j) {
    const std::string path = JsonReader::index("least_squares.support", j);
    std::vector<int> columns;
    for (std::size_t c = 0; c < read.array(list[j], path).size(); ++c)
      columns.push_back(
          static_cast<int>(read.integer(list[j][c], JsonReader::index(path, c), 0, num_base - 1)));
    out.push_back(std::move(columns));
  }
  return out;
}

/// Where the batches' values come from: each batch's base64 text, or an array beside the document
/// (`detached`, the batches' values in order, each batch's "factors" then "").
struct FactorValues {
  const std::vector<double>* detached = nullptr;
  std::size_t next = 0;  // the next detached value
};

/// One batch: its samples and every joint's upper triangle, row by row, in one base64 string.
LeastSquaresSummary::Batch batchFrom(const JsonReader& read, const json& value,
                                     const std::string& path,
                                     const std::vector<std::vector<int>>& support,
                                     FactorValues& source) {
  read.object(value, path);
  read.onlyKeys(value, path, {"samples", "factors"});
  LeastSquaresSummary::Batch out;
  out.samples = read.integer(value, path, "samples", 1, std::numeric_limits<int>::max());
  std::vector<double> values;
  const std::string text = read.string(value, path, "factors");
  if (source.detached != nullptr) {
    if (!text.empty()) read.fail(JsonReader::join(path, "factors"), "expected \"\" (detached)");
    std::size_t count = 0;
    for (const std::vector<int>& s : support) count += (s.size() + 1) * (s.size() + 2) / 2;
    if (source.next + count > source.detached->size())
      read.fail(JsonReader::join(path, "factors"), "the detached values end before this batch's");
    const auto first = source.detached->begin() + static_cast<long>(source.next);
    values.assign(first, first + static_cast<long>(count));
    source.next += count;
  } else {
    try {
      values = doublesFromBase64(text);
    } catch (const InputError& e) {
      read.fail(JsonReader::join(path, "factors"), e.what());
    }
  }
  std::size_t at = 0;
  for (const std::vector<int>& s : support) {
    const auto cols = static_cast<Eigen::Index>(s.size()) + 1;
    Eigen::MatrixXd r = Eigen::MatrixXd::Zero(cols, cols);
    for (Eigen::Index i = 0; i < cols; ++i)
      for (Eigen::Index k = i; k < cols; ++k) {
        if (at >= values.size())
          read.fail(JsonReader::join(path, "factors"), "too few values for the joints' supports");
        r(i, k) = values[at++];
      }
    out.factors.push_back(std::move(r));
  }
  if (at != values.size())
    read.fail(JsonReader::join(path, "factors"), "more values than the joints' supports hold");
  return out;
}

}  // namespace

Summary summaryFrom(const json& document, const std::string& file,
                    const std::vector<double>* detached) {
  const JsonReader read(file);
  if (!isDocumentOfKind(document, kSummaryDocument))
    read.fail("kind", std::string("not a summary (expected kind ") + kSummaryDocument.kind +
                          ", which dynid summarize writes)");
  read.header(document, kSummaryDocument.schema_version, kSummaryDocument.kind);
  read.onlyKeys(document, "",
                {"schema_version", "kind", "model", "model_source", "structural", "base_parameters",
                 "samples", "sources", "least_squares", "provenance"});
  if (document.contains("provenance")) provenanceFrom(document, file);
  Summary out;
  out.model = modelFromJson(read.object(read.field(document, "", "model"), "model").dump(), file);
  out.model_source =
      modelSourceFrom(read.field(document, "", "model_source"), file, "model_source");
  const json& structural = read.object(read.field(document, "", "structural"), "structural");
  read.onlyKeys(structural, "structural", {"samples", "seed", "tolerance"});
  out.structural.samples =
      static_cast<int>(read.integer(structural, "structural", "samples", 0, 1000000000));
  out.structural.seed = read.unsignedInteger(structural, "structural", "seed");
  out.structural.tolerance = read.number(structural, "structural", "tolerance", 0.0, 1.0);
  out.base_names = read.strings(read.field(document, "", "base_parameters"), "base_parameters");
  const int joints = out.model.numJoints();
  const auto num_base = static_cast<int>(out.base_names.size());
  if (num_base < 1) read.fail("base_parameters", "empty");
  const json& sources = read.array(read.field(document, "", "sources"), "sources");
  for (std::size_t i = 0; i < sources.size(); ++i)
    out.sources.push_back(sourceFrom(read, sources[i], JsonReader::index("sources", i), joints));
  const json& ls = read.object(read.field(document, "", "least_squares"), "least_squares");
  read.onlyKeys(ls, "least_squares",
                {"encoding", "support", "fitted_rows", "tau_squared", "max_abs_tau", "batches"});
  if (read.string(ls, "least_squares", "encoding") != kSummaryEncoding)
    read.fail("least_squares.encoding", std::string("expected \"") + kSummaryEncoding + "\"");
  const std::vector<std::vector<int>> support =
      supportFrom(read, read.field(ls, "least_squares", "support"), joints, num_base);
  const json& batches =
      read.array(read.field(ls, "least_squares", "batches"), "least_squares.batches");
  std::vector<LeastSquaresSummary::Batch> parts;
  FactorValues source{detached, 0};
  for (std::size_t i = 0; i < batches.size(); ++i)
    parts.push_back(batchFrom(read, batches[i], JsonReader::index("least_squares.batches", i),
                              support, source));
  if (detached != nullptr && source.next != detached->size())
    read.fail("least_squares.batches", "more detached values than the batches hold");
  try {
    out.factors = LeastSquaresSummary(num_base, support, std::move(parts),
                                      read.vector(read.field(ls, "least_squares", "fitted_rows"),
                                                  "least_squares.fitted_rows", joints),
                                      read.vector(read.field(ls, "least_squares", "tau_squared"),
                                                  "least_squares.tau_squared", joints),
                                      read.number(ls, "least_squares", "max_abs_tau", 0.0));
  } catch (const InputError& e) {
    read.fail("least_squares", e.what());
  }
  long long samples = 0;
  for (const SummarySource& s : out.sources) samples += s.samples;
  const long long total = read.integer(document, "", "samples", 0, std::numeric_limits<int>::max());
  if (samples != out.factors.numSamples() || total != samples)
    read.fail("samples", "the sources' samples (" + std::to_string(samples) + "), the batches' (" +
                             std::to_string(out.factors.numSamples()) + ") and samples (" +
                             std::to_string(total) + ") differ");
  return out;
}

Summary readSummary(const std::string& file) {
  return summaryFrom(parseJson(readFile(file), file), file);
}

}  // namespace dynid
