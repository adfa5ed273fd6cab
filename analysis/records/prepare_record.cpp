#include "analysis/records/prepare_record.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

#include "analysis/records/document.hpp"
#include "data/io.hpp"

namespace dynid {

using nlohmann::json;

namespace {
/// A number, or NaN for anything else (data/json_number.hpp's numberOrNan throws on a non-null
/// non-number: a prepare.json written by an older dynid may hold one).
double numberElseNan(const json& x) {
  return x.is_number() ? x.get<double>() : std::numeric_limits<double>::quiet_NaN();
}
}  // namespace

std::optional<PrepareRecord> prepareRecordFrom(const json& p) {
  if (!p.is_object() || p.value("kind", "") != kPrepareDocument.kind) return std::nullopt;
  try {
    PrepareRecord r;
    const json& raw = p.at("raw");
    r.raw_samples = raw.at("samples").get<long>();
    r.median_step = numberElseNan(raw.at("median_step"));
    r.min_step = numberElseNan(raw.at("min_step"));
    r.max_step = numberElseNan(raw.at("max_step"));
    r.repeated_stamps_dropped = raw.at("repeated_stamps_dropped").get<long>();
    r.max_gap = numberElseNan(p.at("max_gap"));
    r.gaps = static_cast<long>(p.at("gaps").size());
    r.runs = static_cast<long>(p.at("runs").size());
    r.dropped_runs = static_cast<long>(p.at("dropped_runs").size());
    r.resampled_rate = p.at("resampled_rate").get<double>();
    const json& f = p.at("filter");
    r.filter_kind = f.at("kind").get<std::string>();
    r.cutoff_hz = f.at("cutoff_hz").get<double>();
    if (r.cutoff_hz > 0.0) {
      r.filter_order = f.at("order").get<int>();
      r.applied_to = f.at("applied_to").get<std::string>();
    }
    if (f.contains("tau_cutoff_hz") && f["tau_cutoff_hz"].is_number()) {
      r.tau_cutoff_hz = f["tau_cutoff_hz"].get<double>();
      if (*r.tau_cutoff_hz > 0.0) r.filter_order = f.at("order").get<int>();
    }
    if (f.contains("cutoff_choice") && f["cutoff_choice"].is_string())
      r.cutoff_choice = f["cutoff_choice"].get<std::string>();
    r.dq = p.at("dq").get<std::string>();
    r.ddq = p.at("ddq").get<std::string>();
    r.trimmed_each_end = numberElseNan(p.at("trimmed_each_end"));
    r.decimate = p.at("decimate").get<int>();
    for (const json& x : p.at("tau_noise_rms")) r.tau_noise_rms.push_back(numberElseNan(x));
    if (p.contains("source") && p["source"].is_object() &&
        p["source"].contains("current_to_torque")) {
      const json& c = p["source"]["current_to_torque"];
      for (const json& x : c.at("torque_constants")) r.torque_constants.push_back(numberElseNan(x));
      for (const json& x : c.at("gear_ratios")) r.gear_ratios.push_back(numberElseNan(x));
    }
    return r;
  } catch (const json::exception&) {
    return std::nullopt;
  }
}

PreparationFound findPreparation(const std::string& data_file) {
  const std::filesystem::path path(data_file);
  const std::string name = path.filename().string();
  if (name != "train.csv" && name != "validate.csv") return {};
  const std::filesystem::path record = path.parent_path() / "prepare.json";
  std::error_code error;
  if (!std::filesystem::is_regular_file(record, error)) return {};
  try {
    const json j = json::parse(readFile(record.string()));
    if (!j.is_object() || j.value("kind", "") != kPrepareDocument.kind) return {};
    return {true, prepareRecordFrom(j)};
  } catch (const std::exception&) {
    // An unreadable record is not the dataset's problem: the report leaves the section out.
    return {};
  }
}

std::optional<TorqueNoise> torqueNoiseOf(const PreparationFound& found, double rate, int joints) {
  if (!found.record || !(rate > 0.0) ||
      found.record->tau_noise_rms.size() != static_cast<std::size_t>(joints))
    return std::nullopt;
  const PrepareRecord& r = *found.record;
  TorqueNoise out;
  out.sigma = Eigen::Map<const Eigen::VectorXd>(r.tau_noise_rms.data(),
                                                static_cast<Eigen::Index>(r.tau_noise_rms.size()));
  if (!out.sigma.allFinite()) return std::nullopt;
  const double cutoff = r.tau_cutoff_hz.value_or(r.cutoff_hz);
  if (cutoff > 0.0 && r.filter_order > 0) {
    if (!(cutoff < 0.5 * rate) || !(r.resampled_rate > 0.0)) return std::nullopt;
    out.order = r.filter_order;
    out.cutoff = cutoff;
    out.rate = rate;
    out.sigma *= std::sqrt(std::min(rate / r.resampled_rate, 1.0));
  }
  return out;
}

}  // namespace dynid
