#include "reports/prepare_report.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>
#include <tuple>

#include "analysis/records/document.hpp"
#include "analysis/records/provenance.hpp"
#include "core/format.hpp"
#include "data/dataset_csv.hpp"
#include "data/json_number.hpp"
#include "reports/output.hpp"
#include "reports/plots.hpp"

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

namespace {

/// Where the log came from: its files or tables and their selectors, recordings' effort source,
/// and the current-to-torque conversion.
nlohmann::json sourceJson(const LogSource& source, const PrepareOptions& options) {
  const char* tau_key = source.current ? "current" : "tau";
  nlohmann::json sources =
      source.arrays != nullptr
          ? nlohmann::json{{"arrays", "in memory (Python prepare(t=, q=, ...))"}}
      : source.tables.empty()
          ? nlohmann::json{{"time", source.time_file},
                           {"q", source.q_file},
                           {"dq", source.dq_file},
                           {"ddq", source.ddq_file},
                           {tau_key, source.tau_file}}
          : nlohmann::json{{"tables", source.tables},   {"time", source.time_column},
                           {"q", source.q_columns},     {"dq", source.dq_columns},
                           {"ddq", source.ddq_columns}, {tau_key, source.tau_columns}};
  if (!source.effort_topic.empty()) sources["effort_topic"] = source.effort_topic;
  if (!source.effort_table.empty()) sources["effort_log"] = source.effort_table;
  if (source.current)
    sources["current_to_torque"] = {
        {"torque_constants", numbersOrNull(options.torque_constants)},
        {"gear_ratios", options.gear_ratios.size() > 0 ? numbersOrNull(options.gear_ratios)
                                                       : numbersOrNull(Eigen::VectorXd::Ones(
                                                             options.torque_constants.size()))},
        {"torque", "current x torque constant x gear ratio (joint side)"}};
  return sources;
}

/// Per table, the columns each signal was read from.
nlohmann::json columnsJson(const LogSource& source, const PrepareOutcome& o) {
  const char* tau_key = source.current ? "current" : "tau";
  nlohmann::json columns = nlohmann::json::array();
  for (std::size_t f = 0; f < o.columns.size(); ++f) {
    const LogColumns& c = o.columns[f];
    nlohmann::json entry = {{"file", source.tables.at(f)}, {"time", c.time}, {"q", c.q}};
    entry[tau_key] = c.tau;
    if (!c.dq.empty()) entry["dq"] = c.dq;
    if (!c.ddq.empty()) entry["ddq"] = c.ddq;
    columns.push_back(entry);
  }
  return columns;
}

/// The shortest decimal that reads back as the 64-bit origin (an epoch in ns: its 19 digits;
/// 1700000000.00025 as written, not the 21 digits of its nearest binary value), in fixed-point
/// (an epoch reads as one), scientific only when 30 decimals do not read back.
std::string exactOrigin(long double time_origin) {
  char origin[128] = "";
  for (int decimals = 0;; ++decimals) {
    std::snprintf(origin, sizeof(origin), "%.*Lf", decimals, time_origin);
    if (std::strtold(origin, nullptr) == time_origin) break;
    if (decimals == 30) {
      std::snprintf(origin, sizeof(origin), "%.21Lg", time_origin);
      break;
    }
  }
  return origin;
}

}  // namespace

nlohmann::json prepareJson(const LogSource& source, const PrepareOptions& options,
                           const PrepareOutcome& o) {
  nlohmann::json runs = nlohmann::json::array(), dropped = nlohmann::json::array(),
                 gaps = nlohmann::json::array();
  for (const PreparedRun& r : o.runs) runs.push_back(runJson(r));
  for (const PreparedRun& r : o.dropped_runs) dropped.push_back(runJson(r));
  for (const auto& [at, length] : o.gaps) gaps.push_back({{"at", at}, {"length", length}});
  const nlohmann::json sources = sourceJson(source, options);
  const std::string derivatives =
      o.savgol_window > 0 ? "Savitzky-Golay (degree " + std::to_string(options.savgol_degree) +
                                ", " + std::to_string(o.savgol_window) + " samples)"
                          : std::string("central differences");
  nlohmann::json ranges = nlohmann::json::array(), held_runs = nlohmann::json::array();
  for (const auto& [from, to] : options.validate_ranges) ranges.push_back({from, to});
  for (int r : options.validate_runs) held_runs.push_back(r + 1);
  const nlohmann::json held_out = {{"fraction_of_each_run", options.validate_fraction},
                                   {"runs", held_runs},
                                   {"time_ranges", ranges}};
  const nlohmann::json columns = columnsJson(source, o);
  nlohmann::json rest = nlohmann::json::array();
  for (const RestAtEnds& r : o.rest)
    rest.push_back({{"file", r.file},
                    {"start", r.start},
                    {"end", r.end},
                    {"at_rest_first", r.leading},
                    {"at_rest_last", r.trailing}});
  nlohmann::json windows = nlohmann::json::array(), row_windows = nlohmann::json::array();
  for (const auto& [from, to] : options.windows) windows.push_back({from, to});
  for (const auto& [from, to] : options.row_windows) row_windows.push_back({from, to});
  const std::string origin = exactOrigin(o.time_origin);
  return {
      {"schema_version", kPrepareDocument.schema_version},
      {"kind", kPrepareDocument.kind},
      {"source", sources},
      {"columns", columns},
      {"time_origin",
       {{"seconds", static_cast<double>(o.time_origin)},
        {"exact", origin},
        {"meaning", "the log's first stamp: every time here and in the datasets is stamp - this"}}},
      {"windows", {{"time", windows}, {"rows", row_windows}}},
      {"rest_at_ends", rest},
      {"warnings", o.warnings},
      {"raw",
       {{"samples", o.raw_samples},
        {"repeated_stamps_dropped", o.repeated_stamps},
        {"missing_rows_skipped", o.skipped_missing},
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
      {"rate_choice", o.rate_reason},
      {"filter",
       {{"kind", o.cutoff > 0.0 ? "Butterworth low-pass, zero phase (forward-backward)" : "none"},
        {"order", o.order},
        {"cutoff_hz", o.cutoff},
        {"cutoff_choice", o.cutoff_reason},
        {"trajectory_band_hz", o.trajectory_band},
        {"noise_edge_hz", o.noise_edge},
        {"applied_to", o.tau_cutoff == o.cutoff ? std::string("q, dq, tau (parallel filtering)")
                       : o.tau_cutoff > 0.0
                           ? "q, dq; tau with its own cutoff (tau_cutoff_hz)"
                           : "q, dq; tau not filtered (--tau-cutoff none: the raw resampled "
                             "torque)"},
        {"tau_cutoff_hz", o.tau_cutoff}}},
      {"dq", o.dq_derived ? derivatives + " of the filtered q" : std::string("logged, filtered")},
      {"ddq",
       o.ddq_logged
           ? std::string("logged, filtered")
           : derivatives + (o.dq_derived && o.savgol_window > 0 ? " of the filtered q" : " of dq")},
      {"trimmed_each_end", o.trim},
      {"decimate", o.decimate},
      {"samples", {{"train", o.trainSamples()}, {"validate", o.validateSamples()}}},
      {"held_out", held_out},
      {"tau_noise_rms", numbersOrNull(o.tau_noise)}};
}

std::optional<std::string> spectrumFigure(const PrepareOutcome& o) {
  const Spectrum& q = o.q_spectrum;
  const Spectrum& tau = o.tau_spectrum;
  if (q.frequency.size() < 3) return std::nullopt;
  PlotScript s;
  s << "set terminal svg size 900,420 font 'sans,11' background rgb 'white'\n"
    << "set title 'power spectra of the resampled log (each joint normalised to unit power, "
       "summed)'\n"
    << "set logscale xy\nset grid\nset key top right\nset xlabel 'frequency [Hz]'\n"
    << "set ylabel 'density [1/Hz]'\nset format y '10^{%L}'\n";
  PlotRows rows;
  for (Eigen::Index k = 1; k < q.frequency.size(); ++k)
    rows.append({q.frequency[k], std::max(q.density[k], 1e-30), std::max(tau.density[k], 1e-30)});
  s << "$s << EOD\n" << rows << "EOD\n";
  const auto line = [&](double f, const char* colour, const char* label) {
    if (f > 0.0)
      s << "set arrow from " << f << ", graph 0 to " << f << ", graph 1 nohead lw 1.5 lc rgb "
        << gnuplotString(colour) << "\nset label " << gnuplotString(label) << " at " << f
        << ", graph 0.95 offset 0.5,0 tc rgb " << gnuplotString(colour) << "\n";
  };
  line(o.trajectory_band, "#228833", "trajectory band");
  if (o.cutoff > 0.0) line(o.cutoff, "#aa3377", "cutoff");
  s << "plot $s using 1:2 with lines lw 1.5 lc rgb '#4477aa' title 'q', "
       "$s using 1:3 with lines lw 1 lc rgb '#ee6677' title 'tau'\n";
  return gnuplotSvg(s);
}

std::optional<std::string> filteredFigure(const PrepareOutcome& o) {
  if (o.excerpt_time.size() < 2 || o.tau_noise.size() == 0) return std::nullopt;
  Eigen::Index joint = 0;
  o.tau_noise.maxCoeff(&joint);
  PlotScript s;
  s.precision(9);
  s << "set terminal svg size 900,380 font 'sans,11' background rgb 'white'\n"
    << "set title 'joint " << static_cast<long>(joint + 1)
    << " (the noisiest): resampled torque before and after the zero-phase filter'\n"
    << "set grid\nset key top right\nset xlabel 't [s]'\nset ylabel 'tau"
    << static_cast<long>(joint + 1) << " [N m]'\n$e << EOD\n";
  PlotRows rows;
  for (Eigen::Index k = 0; k < o.excerpt_time.size(); ++k)
    rows.append({o.excerpt_time[k], o.excerpt_raw(k, joint), o.excerpt_filtered(k, joint)});
  s << rows
    << "EOD\nplot $e using 1:2 with lines lw 1 lc rgb '#bbbbbb' title 'raw (resampled)', "
       "$e using 1:3 with lines lw 2 lc rgb '#4477aa' title 'filtered'\n";
  return gnuplotSvg(s);
}

namespace {

/// validate_raw.csv: the held-out part's raw torques at the log's stamps (t, tau1..taun).
void writeRawHeldOut(AtomicWriter& raw, const PrepareOutcome& outcome) {
  std::string line = "t";
  for (Eigen::Index j = 0; j < outcome.raw_validate_tau.cols(); ++j)
    line.append(",tau").append(std::to_string(j + 1));
  raw.write(line + "\n");
  for (Eigen::Index k = 0; k < outcome.raw_validate_time.size(); ++k) {
    line = formatNumber(outcome.raw_validate_time[k]);
    for (Eigen::Index j = 0; j < outcome.raw_validate_tau.cols(); ++j)
      line.append(",").append(formatNumber(outcome.raw_validate_tau(k, j)));
    raw.write(line + "\n");
  }
}

/// The summary's words on the filter and the derivatives.
void describeProcessing(std::ostream& out, const PrepareOutcome& outcome) {
  if (outcome.cutoff > 0.0)
    out << "order-" << outcome.order << " Butterworth at " << outcome.cutoff
        << " Hz (zero phase), ";
  else
    out << "no filter, ";
  if (outcome.tau_cutoff != outcome.cutoff)
    out << (outcome.tau_cutoff > 0.0 ? "tau at " + formatNumber(outcome.tau_cutoff) + " Hz, "
                                     : std::string("tau unfiltered, "));
  const std::string method =
      outcome.savgol_window > 0
          ? "Savitzky-Golay (" + std::to_string(outcome.savgol_window) + " samples)"
          : std::string("central differences");
  if (outcome.dq_derived)
    out << (outcome.ddq_logged ? "dq by " + method + ", ddq logged" : "dq and ddq by " + method);
  else
    out << (outcome.ddq_logged ? std::string("dq and ddq logged") : "ddq by " + method);
}

}  // namespace

std::string writePrepared(const std::string& dir, const LogSource& source,
                          const PrepareOptions& options, const PrepareOutcome& outcome,
                          int threads) {
  OutputSet set(dir);  // train.csv, validate.csv, prepare.json and the figures: all or nothing
  // The datasets' numbers formatted on the threads (the same bytes): on an hour-long log, most
  // of the time the outputs take (docs/PERFORMANCE.md).
  ThreadPool pool(threads);
  for (const auto& [name, memory, scratch] :
       {std::tuple{"train.csv", &outcome.train, outcome.scratch_train.get()},
        std::tuple{"validate.csv", &outcome.validate, outcome.scratch_validate.get()}}) {
    if (name == std::string("validate.csv") && outcome.validateSamples() == 0) continue;
    if (scratch == nullptr) {
      writeDatasetCsv(set.stream(name), *memory, &pool);
      continue;
    }
    // Read back from the scratch file a few blocks of rows at a time (prepareLog's scratch_dir).
    writeDatasetCsv(
        set.stream(name), scratch->numJoints(), static_cast<int>(scratch->numSamples()),
        [from = scratch](int first, int last, Trajectory& chunk) {
          from->rows(first, last, chunk);
        },
        &pool);
  }
  if (options.keep_raw_torque) writeRawHeldOut(set.stream("validate_raw.csv"), outcome);
  std::vector<std::pair<std::string, std::string>> files = {
      {"prepare.json", jsonText(withProvenance(prepareJson(source, options, outcome)), 2) + "\n"}};
  std::vector<std::string> figures;
  const std::vector<std::optional<std::string>> svgs = drawConcurrently(
      {[&] { return spectrumFigure(outcome); }, [&] { return filteredFigure(outcome); }});
  const char* names[] = {"spectrum.svg", "filtered.svg"};
  for (std::size_t k = 0; k < svgs.size(); ++k)
    if (svgs[k]) {
      files.emplace_back(names[k], *svgs[k]);
      figures.push_back(names[k]);
    }
  for (const auto& [name, content] : files) set.add(name, content);
  set.publish();
  std::ostringstream out;
  out << "prepared " << outcome.raw_samples << " raw samples (median step "
      << outcome.median_step * 1e3 << " ms, " << outcome.min_step * 1e3 << " to "
      << outcome.max_step * 1e3 << " ms; " << outcome.gaps.size() << " gaps over "
      << outcome.max_gap * 1e3 << " ms; " << outcome.repeated_stamps << " repeated stamps and "
      << outcome.stalled_repeats << " stalled repeats dropped)\n"
      << "  " << outcome.runs.size() << " runs at " << outcome.rate << " Hz, ";
  describeProcessing(out, outcome);
  out << ", " << outcome.trim << " s trimmed at each end, every " << outcome.decimate << " kept\n"
      << "wrote " << dir << "/train.csv (" << outcome.trainSamples() << " samples)";
  if (outcome.validateSamples() > 0)
    out << ", " << dir << "/validate.csv (" << outcome.validateSamples() << ")";
  if (options.keep_raw_torque)
    out << ", " << dir << "/validate_raw.csv (" << outcome.raw_validate_time.size()
        << " raw torque samples)";
  out << ", " << dir << "/prepare.json";
  for (const std::string& name : figures) out << ", " << dir << "/" << name;
  out << "\n  rate: " << outcome.rate_reason
      << "\n  cutoff: " << (outcome.cutoff_reason.empty() ? "given" : outcome.cutoff_reason)
      << "\n";
  if (!outcome.columns.empty()) {
    const LogColumns& c = outcome.columns.front();
    out << "  joints from columns (q, " << (source.current ? "current" : "tau") << "):";
    for (std::size_t j = 0; j < c.q.size(); ++j)
      out << (j == 0 ? " " : ", ") << j + 1 << ": " << c.q[j] << ", " << c.tau[j];
    out << "\n";
  }

  if (figures.empty()) out << "warning: gnuplot did not run: no spectrum.svg or filtered.svg\n";
  return out.str();
}

}  // namespace dynid
