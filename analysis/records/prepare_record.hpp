// prepare.json (dynid prepare, rendered by reports/prepare_report) read back: what an estimate's
// report says of the preprocessing of the dataset it was identified from.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "search/refinement/combined.hpp"

namespace dynid {

/// The fields of prepare.json that an identification report restates.
struct PrepareRecord {
  long raw_samples = 0;
  double median_step = 0.0, min_step = 0.0, max_step = 0.0;  // [s]; NaN when null
  long repeated_stamps_dropped = 0;
  double max_gap = 0.0;  // [s]
  long gaps = 0, runs = 0, dropped_runs = 0;
  double resampled_rate = 0.0;  // [Hz]
  std::string filter_kind;
  int filter_order = 0;
  double cutoff_hz = 0.0;  // 0: no filter
  /// The torque's own cutoff (prepare --tau-cutoff; 0: the torque was not filtered); absent in a
  /// record written before it existed (then cutoff_hz's).
  std::optional<double> tau_cutoff_hz;
  std::string applied_to;
  std::optional<std::string> cutoff_choice;  // why this cutoff (--cutoff auto)
  std::string dq, ddq;                       // how each was obtained
  double trimmed_each_end = 0.0;             // [s]; NaN when null
  int decimate = 1;
  std::vector<double> tau_noise_rms;  // per joint [N m]; NaN where null
  /// With motor currents (prepare --torque-constants): the constants and gear ratios used, per
  /// joint; empty when the log gave torques.
  std::vector<double> torque_constants, gear_ratios;
};

/// The record in a prepare.json document; std::nullopt when it is not one (another kind or
/// schema version) or lacks a field this version reads.
std::optional<PrepareRecord> prepareRecordFrom(const nlohmann::json& document);

/// What an identification finds beside its training data.
struct PreparationFound {
  bool present = false;                 // a prepare.json of kind dynid.prepare beside the data
  std::optional<PrepareRecord> record;  // null when present but unreadable by this version
};
/// The prepare.json beside `data_file` when that file is a `dynid prepare` output (train.csv or
/// validate.csv); an unreadable record is not the dataset's problem and is reported as such.
PreparationFound findPreparation(const std::string& data_file);

/// What a prepared log's record knows of its torque noise, for its GC noise floor at the dataset's
/// `rate` [Hz] (search/refinement/combined.hpp's gcNoiseFloor): the raw noise level per joint
/// (tau_noise_rms) and the torque's filter; a filtered log decimated to `rate` keeps the filtered
/// noise's variance, so the level is scaled by sqrt(rate / resampled_rate). nullopt when there is
/// no record, it has another joint count than `joints`, a joint's level is unknown, or the filter
/// does not fit below rate / 2.
std::optional<TorqueNoise> torqueNoiseOf(const PreparationFound& found, double rate, int joints);

}  // namespace dynid
