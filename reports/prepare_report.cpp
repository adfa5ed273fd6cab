#include "reports/prepare_report.hpp"

#include <filesystem>
#include <sstream>

#include "data/dataset_csv.hpp"
#include "data/json_number.hpp"
#include "reports/output.hpp"

namespace dynid {

namespace {
nlohmann::json runJson(const PreparedRun& r) {
  return {{"file", r.file},
          {"start", r.start},
          {"end", r.end},
          {"time_offset", r.time_offset},
          {"raw_samples", r.raw_samples},
          {"samples", r.samples}};
}
}  // namespace

nlohmann::json prepareJson(const LogSource& source, const PrepareOptions& options,
                           const PrepareOutcome& o) {
  nlohmann::json runs = nlohmann::json::array(), dropped = nlohmann::json::array(),
                 gaps = nlohmann::json::array();
  for (const PreparedRun& r : o.runs) runs.push_back(runJson(r));
  for (const PreparedRun& r : o.dropped_runs) dropped.push_back(runJson(r));
  for (const auto& [at, length] : o.gaps) gaps.push_back({{"at", at}, {"length", length}});
  const char* tau_key = source.current ? "current" : "tau";
  nlohmann::json sources = source.tables.empty() ? nlohmann::json{{"time", source.time_file},
                                                                  {"q", source.q_file},
                                                                  {"dq", source.dq_file},
                                                                  {tau_key, source.tau_file}}
                                                 : nlohmann::json{{"tables", source.tables},
                                                                  {"time", source.time_column},
                                                                  {"q", source.q_columns},
                                                                  {"dq", source.dq_columns},
                                                                  {tau_key, source.tau_columns}};
  if (source.current)
    sources["current_to_torque"] = {
        {"torque_constants", numbersOrNull(options.torque_constants)},
        {"gear_ratios", options.gear_ratios.size() > 0 ? numbersOrNull(options.gear_ratios)
                                                       : numbersOrNull(Eigen::VectorXd::Ones(
                                                             options.torque_constants.size()))},
        {"torque", "current x torque constant x gear ratio (joint side)"}};
  return {
      {"schema_version", kPrepareSchemaVersion},
      {"kind", "dynid.prepare"},
      {"source", sources},
      {"raw",
       {{"samples", o.raw_samples},
        {"repeated_stamps_dropped", o.repeated_stamps},
        {"stalled_repeats_dropped", o.stalled_repeats},
        {"out_of_order_stamps", o.unsorted_stamps},
        {"median_step", o.median_step},
        {"min_step", o.min_step},
        {"max_step", o.max_step}}},
      {"gaps", gaps},
      {"max_gap", o.max_gap},
      {"runs", runs},
      {"dropped_runs", dropped},
      {"resampled_rate", o.rate},
      {"filter",
       {{"kind", o.cutoff > 0.0 ? "Butterworth low-pass, zero phase (forward-backward)" : "none"},
        {"order", o.order},
        {"cutoff_hz", o.cutoff},
        {"applied_to", "q, dq, tau (parallel filtering)"}}},
      {"dq", o.dq_derived ? "central differences of the filtered q" : "logged, filtered"},
      {"ddq", "central differences of dq"},
      {"trimmed_each_end", o.trim},
      {"decimate", o.decimate},
      {"samples", {{"train", o.train.numSamples()}, {"validate", o.validate.numSamples()}}},
      {"tau_noise_rms", numbersOrNull(o.tau_noise)}};
}

std::string writePrepared(const std::string& dir, const LogSource& source,
                          const PrepareOptions& options, const PrepareOutcome& outcome) {
  std::filesystem::create_directories(dir);
  writeDatasetCsv(dir + "/train.csv", outcome.train);
  if (outcome.validate.numSamples() > 0) writeDatasetCsv(dir + "/validate.csv", outcome.validate);
  writeReportFiles(dir, {{"prepare.json", prepareJson(source, options, outcome).dump(2) + "\n"}});
  std::ostringstream out;
  out << "prepared " << outcome.raw_samples << " raw samples (median step "
      << outcome.median_step * 1e3 << " ms, " << outcome.min_step * 1e3 << " to "
      << outcome.max_step * 1e3 << " ms; " << outcome.gaps.size() << " gaps over "
      << outcome.max_gap * 1e3 << " ms; " << outcome.repeated_stamps << " repeated stamps and "
      << outcome.stalled_repeats << " stalled repeats dropped)\n"
      << "  " << outcome.runs.size() << " runs at " << outcome.rate << " Hz, ";
  if (outcome.cutoff > 0.0)
    out << "order-" << outcome.order << " Butterworth at " << outcome.cutoff
        << " Hz (zero phase), ";
  else
    out << "no filter, ";
  out << (outcome.dq_derived ? "dq and ddq" : "ddq") << " by central differences, " << outcome.trim
      << " s trimmed at each end, every " << outcome.decimate << " kept\n"
      << "wrote " << dir << "/train.csv (" << outcome.train.numSamples() << " samples)";
  if (outcome.validate.numSamples() > 0)
    out << ", " << dir << "/validate.csv (" << outcome.validate.numSamples() << ")";
  out << " and " << dir << "/prepare.json\n";
  return out.str();
}

}  // namespace dynid
