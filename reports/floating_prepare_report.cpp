#include "reports/floating_prepare_report.hpp"

#include <sstream>

#include "analysis/records/document.hpp"
#include "core/format.hpp"

namespace dynid {

using json = nlohmann::json;

json floatingPrepareJson(const FloatingModel& model, const std::string& recording,
                         const FloatingPrepareOutcome& outcome) {
  json topics = json::array();
  for (const FloatingTopicSummary& t : outcome.topics)
    topics.push_back({{"topic", t.topic},
                      {"type", t.type},
                      {"frame", t.frame.empty() ? json(nullptr) : json(t.frame)},
                      {"messages", t.messages},
                      {"repeated_stamps", t.repeated},
                      {"median_step", t.median_step},
                      {"gap_limit", t.gap_limit},
                      {"gaps", t.gaps}});
  const FloatingDataset& d = outcome.dataset;
  json thresholded = json::array();
  for (const auto& [frame, share] : outcome.thresholded)
    thresholded.push_back({{"frame", frame}, {"holding_fraction", share}});
  json report = documentHeader(kFloatingPrepareDocument);
  report.update(
      {{"robot", model.name()},
       {"base_link", model.baseName()},
       {"recording", recording},
       {"topics", topics},
       {"rate", outcome.rate},
       {"rate_reason", outcome.rate_reason},
       {"cutoff", outcome.cutoff},
       {"cutoff_reason", outcome.cutoff_reason},
       {"trim", outcome.trim},
       {"span", {outcome.span_from, outcome.span_to}},
       {"runs", outcome.runs},
       {"runs_dropped", outcome.runs_dropped},
       {"samples", d.numSamples()},
       {"torques", d.hasTorques()},
       {"contact_threshold",
        outcome.contact_threshold > 0.0 ? json(outcome.contact_threshold) : json(nullptr)},
       {"thresholded_contacts", thresholded},
       {"warnings", outcome.warnings}});
  return report;
}

std::string floatingPrepareSummary(const FloatingModel& model,
                                   const FloatingPrepareOutcome& outcome,
                                   const std::string& dataset, const std::string& document) {
  std::ostringstream out;
  out << model.name() << " (floating base " << model.baseName() << "):\n";
  for (const FloatingTopicSummary& t : outcome.topics)
    out << "  " << t.topic << " (" << t.type << (t.frame.empty() ? "" : ", in " + t.frame)
        << "): " << t.messages << (t.type == "table columns" ? " samples" : " messages")
        << ", median step " << formatNumber(t.median_step * 1e3, 4) << " ms"
        << (t.gaps > 0 ? ", " + std::to_string(t.gaps) + " gap(s)" : "")
        << (t.repeated > 0 ? ", " + std::to_string(t.repeated) + " repeated stamp(s) dropped" : "")
        << "\n";
  out << "  every topic resampled to " << formatNumber(outcome.rate, 6) << " Hz ("
      << outcome.rate_reason << ") over " << formatNumber(outcome.span_from, 6) << " to "
      << formatNumber(outcome.span_to, 6) << " s; low-pass "
      << (outcome.cutoff > 0.0 ? formatNumber(outcome.cutoff, 4) + " Hz" : std::string("none"))
      << " (" << outcome.cutoff_reason << "), " << formatNumber(outcome.trim, 4)
      << " s trimmed at each run's ends; " << outcome.runs << " run(s), "
      << outcome.dataset.numSamples() << " samples\n";
  if (!outcome.thresholded.empty()) {
    out << "  contact flags where the force reaches " << formatNumber(outcome.contact_threshold, 6)
        << " N:";
    for (const auto& [frame, share] : outcome.thresholded)
      out << " " << frame << " holds in " << formatNumber(100.0 * share, 3) << " %;";
    out << " the samples\n";
  }
  out << "  wrote " << dataset << " and " << document << "\n";
  return out.str();
}

}  // namespace dynid
