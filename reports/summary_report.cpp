#include "reports/summary_report.hpp"

#include <sstream>

#include "analysis/records/document.hpp"
#include "analysis/records/provenance.hpp"
#include "core/format.hpp"
#include "data/digest/base64.hpp"
#include "data/model_json.hpp"
#include "reports/output.hpp"

namespace dynid {

namespace {

using json = nlohmann::json;

json vectorJson(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

json filterJson(const TorqueFilter& f) {
  if (!f.active()) return nullptr;
  return {{"order", f.order}, {"cutoff_hz", f.cutoff}, {"rate_hz", f.rate}};
}

/// A batch's joints' upper triangles, row by row, in one base64 string (or appended to
/// `detached`).
json batchJson(const LeastSquaresSummary::Batch& batch, std::vector<double>* detached) {
  std::vector<double> own;
  std::vector<double>& values = detached != nullptr ? *detached : own;
  for (const Eigen::MatrixXd& r : batch.factors)
    for (Eigen::Index i = 0; i < r.rows(); ++i)
      for (Eigen::Index k = i; k < r.cols(); ++k) values.push_back(r(i, k));
  return {{"samples", batch.samples},
          {"factors",
           detached != nullptr ? std::string() : doublesToBase64(values.data(), values.size())}};
}

}  // namespace

json summarySourceJson(const SummarySource& s) {
  return {{"file", s.file},
          {"sha256", s.sha256},
          {"samples", s.samples},
          {"rest_velocity", s.rest_velocity},
          {"torque_filter", filterJson(s.torque_filter)},
          {"torque_filter_source", s.torque_filter_source}};
}

json summaryJson(const Summary& summary, std::vector<double>* detached) {
  json out = documentHeader(kSummaryDocument);
  out["model"] = json::parse(modelToJson(summary.model));
  out["model_source"] = modelSourceJson(summary.model_source);
  out["structural"] = {{"samples", summary.structural.samples},
                       {"seed", summary.structural.seed},
                       {"tolerance", summary.structural.tolerance}};
  out["base_parameters"] = summary.base_names;
  out["samples"] = summary.factors.numSamples();
  json sources = json::array();
  for (const SummarySource& s : summary.sources) sources.push_back(summarySourceJson(s));
  out["sources"] = std::move(sources);
  const LeastSquaresSummary& f = summary.factors;
  json batches = json::array();
  if (detached != nullptr) detached->reserve(static_cast<std::size_t>(f.numValues()));
  for (const LeastSquaresSummary::Batch& b : f.batches()) batches.push_back(batchJson(b, detached));
  out["least_squares"] = {{"encoding", kSummaryEncoding},
                          {"support", f.support()},
                          {"fitted_rows", vectorJson(f.fittedRows())},
                          {"tau_squared", vectorJson(f.tauSquared())},
                          {"max_abs_tau", f.maxAbsTau()},
                          {"batches", std::move(batches)}};
  return out;
}

std::string writeSummaries(const std::string& dir,
                           const std::vector<std::pair<std::string, Summary>>& named) {
  OutputSet set(dir);
  std::ostringstream lines;
  for (const auto& [name, summary] : named) {
    const std::string text = withProvenance(summaryJson(summary)).dump(1) + "\n";
    set.add(name, text);
    lines << dir << "/" << name << ": " << summary.sources.size()
          << (summary.sources.size() == 1 ? " log, " : " logs, ") << summary.factors.numSamples()
          << " samples in " << summary.factors.batches().size() << " batches ("
          << formatNumber(static_cast<double>(text.size()) / 1e6, 3) << " MB)\n";
  }
  set.publish();
  return lines.str();
}

}  // namespace dynid
