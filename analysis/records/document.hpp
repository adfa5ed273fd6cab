// The records wing: every document dynid writes and reads back (estimate.json, search.json and its
// checkpoint, refine.json, prepare.json, excitation.json, and the rest) has its kind and schema
// version here, and a typed record with its reader in this wing (search_record, estimate_record,
// prepare_record, excitation_record). reports/ renders records into documents; analysis/ reads
// them back only through these readers, never by string key. Errors in a file read here are
// ParseErrors naming the file and the JSON path of the field.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace dynid {

/// A document's identity: every dynid JSON document starts with these two keys.
struct DocumentType {
  const char* kind;  // "dynid.estimate"
  int schema_version;
};

// estimate.json 2: rest_velocity (each joint's rest velocity, how it was measured) and the held-out
// validation's at_rest; version 1 documents are still read (every joint's rest velocity 0).
// estimate.json 3: base_covariance.policy (the covariance's policy: batch means of the scores, its
// batch length, inflation over the white covariance and the residuals' autocorrelation); versions 1
// and 2 are still read (their covariance is the white one).
// estimate.json 5: model (the robot it was made for, as a dynid JSON model) and model_source (the
// spec, the file's name and SHA-256): it is read without the robot's file, from any folder.
// estimate.json 6, and every document a command writes (the versions below that say "provenance"):
// provenance (what made it: dynid's version and commit, the command, the working directory, the
// inputs' SHA-256, seed, threads, when and how long, the document's own time fields;
// records/provenance.hpp). The earlier versions are still read (they say nothing of it).
// estimate.json 7: data.sources, the logs of the summaries it was identified from (an identify
// request's `summary`; absent for a dataset). Version 6 is read (every earlier one, as said above).
// estimate.json 8: front (an identify request's `front_weights`: the combined estimator's points,
// each measured on the held-out data, and the weight chosen); absent without. Version 7 is read.
inline constexpr DocumentType kEstimateDocument{"dynid.estimate", 8};  // identify
// identifiability.json 2: provenance.
inline constexpr DocumentType kIdentifiabilityDocument{"dynid.identifiability", 2};
// identifiability --floating-base: what each sensor set of a floating robot determines.
inline constexpr DocumentType kFloatingIdentifiabilityDocument{"dynid.floating_identifiability", 1};
// identify --floating-base: each sensor set's estimate on a floating-base dataset (with pc, each
// set's `physical`).
inline constexpr DocumentType kFloatingIdentificationDocument{"dynid.floating_identification", 4};
// prepare --floating-base: a floating robot's recording prepared into a floating dataset.
inline constexpr DocumentType kFloatingPrepareDocument{"dynid.floating_prepare", 2};
// search.json and refine.json 2: model (the robot searched or refined on, nominal parameters) and
// model_source; search.json 1 is still read by refine --from. 3: provenance (search.json 2 is
// read).
inline constexpr DocumentType kSearchDocument{"dynid.search", 3};
inline constexpr DocumentType kCheckpointDocument{"dynid.search_checkpoint", 1};
inline constexpr DocumentType kRefineDocument{"dynid.refine", 3};  // 3: provenance
// prepare.json 2: sources.tables (a list; was sources.table), runs' file and time_offset, stalled
// repeats, current_to_torque. 3: provenance.
inline constexpr DocumentType kPrepareDocument{"dynid.prepare", 3};
// excitation.json 2: payload_link (dynid excite --payload); version 1 documents are still read.
// 3: model is the robot designed for (a dynid JSON model; it was its name) and model_source.
// 4: provenance. 5: stand (the stand orientations `--stands` chose; null without).
inline constexpr DocumentType kExcitationDocument{"dynid.excitation", 5};
// standing_excitation.json (excite --floating-base --stance): a standing robot's designed sway,
// the stance and contacts it is for, what every sensor set determines on it and on the default
// sway.
inline constexpr DocumentType kStandingExcitationDocument{"dynid.standing_excitation", 1};
// 2: per-joint errors named as in estimate.json (residual_rms, joint_relative_error).
// 3: rest_velocity and at_rest (the prediction at rest: static friction's band). 4: torque_filter
// (the filter the comparison reproduced, or null) and torque_filter_source; compared_rows (the
// errors are over the rows a fit takes: a joint at rest with friction that needs sign(dq) is not).
// 5: model (the robot and parameters predicted with, as a dynid JSON model) and model_source.
// 6: provenance.
inline constexpr DocumentType kPredictionDocument{"dynid.prediction", 6};
// study.json 2: model (the robot studied, nominal parameters) and model_source. 3: provenance.
// 4: front (the combined estimator's points, measured) and choice (the estimate chosen by its
// rule).
// 5: each front point's standard parameters, and choice.estimate (chosen.json, the chosen estimate
// as a dynid JSON model).
inline constexpr DocumentType kStudyDocument{"dynid.study", 5};
inline constexpr DocumentType kDemoDocument{"dynid.demo", 2};               // 2: provenance
inline constexpr DocumentType kModelCheckDocument{"dynid.model_check", 1};  // model check --json
inline constexpr DocumentType kDynamicsDocument{"dynid.dynamics", 1};       // dynamics --json
// payload.json 2: a quantity the log does not determine has `value` null and its number in
// `estimate` (the resolution is its half_width_95). 3: model (the arm the payload was estimated on,
// as a dynid JSON model with its parameters) and model_source. 4: provenance.
inline constexpr DocumentType kPayloadDocument{"dynid.payload", 4};  // dynid payload
// A payload body alone (payload --format json): what --prior reads back. 2: provenance.
inline constexpr DocumentType kPayloadBodyDocument{"dynid.payload_body", 2};
// audit.json 2: dispersion (whether the sigma are too small alike), covariance_policies, each
// parameter's p_scaled.
// audit.json 3: model (the sessions' robot, as the first estimate embeds it; absent for an
// estimate.json before 5) and model_source. 4: provenance.
inline constexpr DocumentType kAuditDocument{"dynid.audit", 4};  // dynid audit
// monitor.json 2: each event's contact_link (contact isolation), calibration_confidence. 3: each
// event's state (rest or moving), the thresholds' version 2. 4: the thresholds' version 3, each
// event's regime (moving: the peak joint's regime; null at rest). 5: model and model_source (the
// arm, as a dynid JSON model with its parameters, and where its robot came from). 6: provenance.
inline constexpr DocumentType kMonitorDocument{"dynid.monitor", 6};  // dynid monitor
/// A monitor's thresholds (thresholds.json), read back by a later monitor --thresholds. 2: the arm
/// states: rest_velocity, thresholds_at_rest (null without), rest_seconds, calibration_rest_rms. 3:
/// moving_regimes (null without): regimes, speed_scale, acceleration_scale, thresholds, seconds.
/// 4: model and model_source (the arm they were set for; thresholds.json only, not the copy in
/// monitor.json, which embeds it once at its top). 5: provenance (thresholds.json only).
inline constexpr DocumentType kMonitorThresholdsDocument{"dynid.monitor_thresholds", 5};
// summary.json (dynid summarize): a least-squares summary of one robot's logs (its batches'
// triangular factors in base64), what an identify request's `summary` is read from.
inline constexpr DocumentType kSummaryDocument{"dynid.summary", 1};
// fleet.json (dynid fleet): robots of one model, the fleet's prior learnt from them, the robots and
// parameters outside it, each robot's estimate alone and with the prior.
inline constexpr DocumentType kFleetDocument{"dynid.fleet", 1};
// A fleet manifest (dynid fleet --manifest): the robots and their logs or summaries.
inline constexpr DocumentType kFleetManifestDocument{"dynid.fleet_manifest", 1};
inline constexpr DocumentType kBatchRunDocument{"dynid.batch.run", 1};
inline constexpr DocumentType kBatchResultsDocument{"dynid.batch.results", 1};

/// {"schema_version": ..., "kind": ...}: a document's first keys.
nlohmann::json documentHeader(const DocumentType& type);

/// The document's schema_version when it is an integer from 1 to `current` - 1 (an earlier
/// version, which its reader takes as it is), else `current` (the header check then names it).
int documentVersion(const nlohmann::json& document, int current);

/// Whether `document` is an object whose "kind" is `type`'s (a string; anything else: false).
bool isDocumentOfKind(const nlohmann::json& document, const DocumentType& type);

/// Parses `text` as JSON; throws ParseError naming `file` ("invalid JSON: ...").
nlohmann::json parseJson(const std::string& text, const std::string& file);

}  // namespace dynid
