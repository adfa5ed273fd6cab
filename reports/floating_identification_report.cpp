#include "reports/floating_identification_report.hpp"

#include <cmath>
#include <sstream>

#include "analysis/records/document.hpp"
#include "core/format.hpp"
#include "data/json_number.hpp"
#include "reports/floating_report.hpp"

namespace dynid {

using nlohmann::json;

namespace {
/// The channels' noise standard deviations the weighted fit used, each null where the data have
/// no such channel or the estimating set does not read it.
json noiseJson(const FloatingIdentifyOutcome& outcome, const FloatingSetEstimate& s) {
  if (outcome.method == FloatingMethod::kOls) return nullptr;
  bool frames = false, wrenches = false;
  for (const Contact& c : outcome.contacts) frames = frames || c.kind == Contact::Kind::kFrame;
  wrenches = !outcome.contacts.empty() && s.variances_from != SensorSet::kTorquesAndContactFlags;
  const bool torques = s.variances_from != SensorSet::kWrenches;
  const auto sd = [](bool read, double variance) {
    return read ? json(std::sqrt(variance)) : json(nullptr);
  };
  return {{"torque", sd(torques, s.variances.torque)},
          {"force", sd(wrenches, s.variances.force)},
          {"moment", sd(wrenches && frames, s.variances.moment)},
          {"estimated_by", sensorSetName(s.variances_from)}};
}

/// The combined estimator's run (null without it): GC errors and torque terms at the start (pc's
/// estimate) and the end, the floor, weight, linearisations, termination, whether it moved.
json combinedJson(const FloatingSetEstimate& s) {
  if (!s.combined) return nullptr;
  const CombinedResult& c = *s.combined;
  return {{"gc_weight", c.gc_weight},
          {"gc_floor", c.gc_floor},
          {"initial_gc", numberOrNull(c.initial_gc)},
          {"final_gc", numberOrNull(c.final_gc)},
          {"initial_torque", numberOrNull(c.initial_torque)},
          {"final_torque", numberOrNull(c.final_torque)},
          {"iterations", c.iterations},
          {"moved", c.moved},
          {"interrupted", c.interrupted},
          {"termination", c.termination},
          {"seconds", c.seconds}};
}

json setJson(const FloatingIdentifyOutcome& outcome, const FloatingSetEstimate& s) {
  const BaseParameters& base = s.base.base;
  json out = {{"sensors", sensorSetName(s.base.set)},
              {"description", sensorSetDescription(s.base.set)},
              {"num_base", base.numBase()},
              {"refused", s.refused.empty() ? json(nullptr) : json(s.refused)}};
  if (!s.refused.empty()) return out;
  json parameters = json::array();
  for (int j = 0; j < base.numBase(); ++j) {
    const double z = (s.fit.beta[j] - s.model_beta[j]) / s.fit.sd[j];
    parameters.push_back({{"name", base.baseName(j)},
                          {"expression", base.expression(j)},
                          {"estimate", s.fit.beta[j]},
                          {"sd", numberOrNull(s.fit.sd[j])},
                          {"model_value", s.model_beta[j]},
                          {"z", numberOrNull(z)}});
  }
  json physical = nullptr;
  if (s.physical)
    physical = {
        {"converged", s.physical->converged},
        {"termination", s.physical->termination},
        {"iterations", s.physical->iterations},
        {"standard", std::vector<double>(s.physical->theta.data(),
                                         s.physical->theta.data() + s.physical->theta.size())}};
  out.update({{"rows", s.fit.rows},
              {"residual_scale", s.fit.residual_scale},
              {"physical", physical},
              {"combined", combinedJson(s)},
              {"noise_sd", noiseJson(outcome, s)},
              {"residual_percent", s.residual_percent},
              {"validation_percent", numberOrNull(s.validation_percent)},
              {"model_error_percent", s.model_error_percent},
              {"model_z_rms", numberOrNull(s.model_z_rms)},
              {"gc_error",
               {{"train", numberOrNull(s.gc_train)},
                {"test", numberOrNull(s.gc_test)},
                {"noise_floor_train", numberOrNull(s.gc_floor_train)},
                {"noise_floor_test", numberOrNull(s.gc_floor_test)}}},
              {"base_parameters", parameters}});
  return out;
}

std::string percent(double x) { return formatNumber(x, 3) + " %"; }

/// How the combined estimator went from pc's estimate (FloatingSetEstimate::combined), or why not.
std::string combinedLine(const CombinedResult& c) {
  // The floor the GC term was held at is the estimate nearest the robot's, not this estimate's
  // own (the set line's parentheses): said in words, so that the two are not read as one.
  const std::string floor = c.gc_floor > 0.0 ? "held at " + formatNumber(c.gc_floor, 3) +
                                                   ", the nearest estimate's noise floor"
                                             : "no noise floor";
  std::string out = "combined from pc's: GC error " + formatNumber(c.initial_gc, 4) + " to " +
                    formatNumber(c.final_gc, 4) + " (" + floor + "), torque term " +
                    formatNumber(c.initial_torque, 4) + " to " + formatNumber(c.final_torque, 4) +
                    " in " + std::to_string(c.iterations) + " linearisations; " + c.termination;
  if (!c.moved) out += " (no step taken: pc's estimate)";
  return out;
}

/// A GC error with its noise floor in parentheses where it has one ("-" where not measured).
std::string withFloor(double error, double floor) {
  return formatNumber(error, 4, "-") +
         (std::isnan(floor) ? std::string() : " (" + formatNumber(floor, 3) + ")");
}

/// The report's paragraph on the GC error: how it was measured, or why not.
std::string gcMarkdown(const FloatingGcSummary& gc) {
  std::ostringstream md;
  if (!gc.refused.empty() && gc.validation_segments == 0) {
    md << "GC error not measured: " << gc.refused << ".\n\n";
    return md.str();
  }
  if (gc.refused.empty())
    md << "The GC error (the paper's measure) rolls " << gc.segments << " segments of "
       << formatNumber(gc.horizon, 4) << " s (" << gc.samples_per_segment
       << " sample periods) of the recorded motion out from their recorded start by each "
          "estimate (ols and wls: its base parameters, the rest the model's), driven by the "
          "recorded joint torques and contact wrenches (a contact known by its flag alone held "
          "still while it holds), and sums the squared differences of q, "
          "dq, the base's "
       << (gc.linear_velocity ? "twist" : "angular velocity")
       << " and rotation angle at their ends";
  else
    md << "GC error not measured on the data: " << gc.refused;
  if (gc.validation_segments > 0)
    md << "; held out, " << gc.validation_segments << " segments";
  else if (!gc.validation_refused.empty())
    md << "; not on the held-out data: " << gc.validation_refused;
  md << ".";
  if (!std::isnan(gc.floor_train) || !std::isnan(gc.floor_test))
    md << " In parentheses, each candidate's noise floor: what the measured inputs' noise alone "
          "gives it (the mean of GC(inputs + noise) - GC(inputs) over "
       << kGcFloorDraws
       << " draws at the channels' estimated variances, the same for every candidate). A GC "
          "error at its floor is all noise; what it has above it is the candidate's own.";
  if (!gc.linear_velocity)
    md << " The base's linear velocity is left out: the data do not record it (an IMU's "
          "dataset holds zero there while the base accelerates).";
  md << "\n\n";
  return md.str();
}

/// The console's line on the GC error: the model's own, or why there is none.
std::string gcSummaryLine(const FloatingGcSummary& gc) {
  if (!gc.refused.empty() && gc.validation_segments == 0)
    return "GC error not measured: " + gc.refused;
  std::string line = "GC error of the model's own parameters " +
                     withFloor(gc.model_train, gc.floor_train) + ", held out " +
                     withFloor(gc.model_test, gc.floor_test);
  if (gc.refused.empty())
    line += "; " + std::to_string(gc.segments) + " segments of " + formatNumber(gc.horizon, 4) +
            " s" + (gc.linear_velocity ? "" : ", the base's linear velocity not recorded");
  else
    line += "; not on the data: " + gc.refused;
  if (!gc.validation_refused.empty()) line += "; not held out: " + gc.validation_refused;
  if (!std::isnan(gc.floor_train) || !std::isnan(gc.floor_test))
    line += "; in parentheses the noise floors (what the inputs' noise alone gives each)";
  return line;
}

/// floating_identification.json's "gc": how the GC errors were measured, the model's own, or why
/// there are none.
json gcJson(const FloatingGcSummary& gc) {
  const auto text = [](const std::string& t) { return t.empty() ? json(nullptr) : json(t); };
  return {
      {"refused", text(gc.refused)},
      {"validation_refused", text(gc.validation_refused)},
      {"horizon", gc.horizon},
      {"samples_per_segment", gc.samples_per_segment},
      {"segments_train", gc.segments},
      {"segments_test", gc.validation_segments},
      {"linear_velocity_compared", gc.linear_velocity},
      {"model", {{"train", numberOrNull(gc.model_train)}, {"test", numberOrNull(gc.model_test)}}},
      {"model_noise_floor",
       {{"train", numberOrNull(gc.floor_train)}, {"test", numberOrNull(gc.floor_test)}}},
      {"note",
       "the paper's GC error on a floating base: segments of the recorded motion rolled out "
       "from their recorded start by each estimate (ols, wls: its base parameters, the rest "
       "the model's), driven by the recorded joint torques and contact wrenches (a contact "
       "known by its flag alone held still while it holds), and the "
       "squared differences of q, dq, the base's twist and rotation angle at their end, "
       "summed over the segments; `model`: the model's own parameters; a noise floor: what "
       "the measured inputs' noise alone gives that candidate (the mean of GC(inputs + "
       "noise) - GC(inputs) over four draws at the channels' estimated variances, the same "
       "draws for every candidate; null with ols, or where the rollout diverged): a GC error "
       "at its floor is all noise, what it has above it is the candidate's own"}};
}

/// The payload's ten parameters with their sd, its mass and centre of mass (in its body's frame).
json payloadJson(const FloatingDataSources& sources, const FloatingIdentifyOutcome& outcome) {
  const std::vector<FloatingPayload>& payloads = sources.payloads;
  if (payloads.empty()) return nullptr;
  json sets = json::array();
  for (std::size_t k = 0; k < payloads.size(); ++k) {
    const FloatingPayload& p = payloads[k];
    json set = {{"sensors", sensorSetName(outcome.sets[k].base.set)},
                {"refused", p.refused.empty() ? json(nullptr) : json(p.refused)}};
    if (p.refused.empty()) {
      json parameters = json::array();
      for (int j = 0; j < kLinkParameterCount; ++j)
        parameters.push_back({{"name", kLinkParameterNames[j]},
                              {"value", p.phi[j]},
                              {"sd", numberOrNull(std::sqrt(p.covariance(j, j)))}});
      set.update({{"parameters", parameters},
                  {"mass", p.phi[0]},
                  {"mass_sd", numberOrNull(std::sqrt(p.covariance(0, 0)))},
                  {"com", json::array({numberOrNull(p.phi[1] / p.phi[0]),
                                       numberOrNull(p.phi[2] / p.phi[0]),
                                       numberOrNull(p.phi[3] / p.phi[0])})},
                  {"residual_scale", p.residual_scale}});
    }
    sets.push_back(set);
  }
  return {{"link", payloads.front().link},
          {"body", payloads.front().body},
          {"from", sources.unloaded.empty() ? "model" : "unloaded_data"},
          {"unloaded", sources.unloaded.empty() ? json(nullptr) : json(sources.unloaded)},
          {"sets", sets}};
}
}  // namespace

json floatingIdentificationJson(const FloatingModel& model, const FloatingIdentifyOutcome& outcome,
                                const FloatingDataSources& sources) {
  json sets = json::array(), contacts = json::array();
  for (const FloatingSetEstimate& s : outcome.sets) sets.push_back(setJson(outcome, s));
  for (const Contact& c : outcome.contacts) contacts.push_back(floatingContactJson(c));
  json report = documentHeader(kFloatingIdentificationDocument);
  report.update(
      {{"robot", model.name()},
       {"base_link", model.baseName()},
       {"joints", model.numJoints()},
       {"drive_terms", driveTermsKeys(model.limbs().driveTerms())},
       {"num_standard", model.numParameters()},
       {"standard_parameters", floatingParameterNames(model)},
       {"data", {{"file", sources.data}, {"samples", outcome.samples}}},
       {"validation", sources.validation.empty() ? json(nullptr)
                                                 : json{{"file", sources.validation},
                                                        {"samples", outcome.validation_samples}}},
       {"contacts", contacts},
       {"motion", floatingMotionName(outcome.motion)},
       {"method", floatingMethodName(outcome.method)},
       {"sets", sets},
       {"gc", gcJson(outcome.gc)},
       {"payload", payloadJson(sources, outcome)}});
  return report;
}

std::string floatingIdentificationMarkdown(const FloatingModel& model,
                                           const FloatingIdentifyOutcome& outcome,
                                           const FloatingDataSources& sources) {
  std::ostringstream md;
  md << "# " << model.name() << "'s base parameters from a floating-base dataset\n\n";
  md << "- Data: `" << sources.data << "`, " << outcome.samples << " samples";
  if (!sources.validation.empty())
    md << "; held out: `" << sources.validation << "`, " << outcome.validation_samples
       << " samples";
  md << "\n- Method: " << floatingMethodName(outcome.method)
     << (outcome.method == FloatingMethod::kWls
             ? " (each channel's noise estimated from the data, every row weighted by it)"
         : outcome.method == FloatingMethod::kPc
             ? " (weighted as wls; every body's pseudo-inertia positive definite, the "
               "non-negative drive terms positive, the model's parameters the prior; sd as wls's, "
               "the constraints taken as inactive)"
         : outcome.method == FloatingMethod::kCombined
             ? " (pc's estimate refined to fit the rows and predict the data's motion together: "
               "the set's pc objective plus the GC error of the data's segments, each normalised "
               "at pc's estimate, the GC term held at its noise floor; sd as pc's)"
             : " (every row alike)")
     << "; motion: " << floatingMotionName(outcome.motion) << "; contacts:";
  if (outcome.contacts.empty()) md << " none";
  for (const Contact& c : outcome.contacts)
    md << " `" << c.name << "` (" << (c.kind == Contact::Kind::kPoint ? "point" : "frame") << ")";
  for (const std::string& w : outcome.warnings) md << "\n- Warning: " << w;
  md << "\n\nThe residual is ||W beta - y|| / ||y|| over the set's rows; the error against the "
        "model compares the estimate with the model's own base parameters (the truth when the "
        "model made the data), in percent of their norm and in standard deviations (z RMS 1: "
        "intervals that hold).\n\n";
  md << gcMarkdown(outcome.gc);
  md << "| sensors | base parameters | residual | held out | from the model | z RMS | GC error | "
        "GC held out |\n|---|---|---|---|---|---|---|---|\n";
  for (const FloatingSetEstimate& s : outcome.sets) {
    md << "| " << sensorSetName(s.base.set) << " | " << s.base.base.numBase() << " | ";
    if (!s.refused.empty()) {
      md << "not estimated: " << s.refused << " | | | | | |\n";
      continue;
    }
    md << percent(s.residual_percent) << " | "
       << (std::isnan(s.validation_percent) ? "-" : percent(s.validation_percent)) << " | "
       << percent(s.model_error_percent) << " | " << formatNumber(s.model_z_rms, 3, "-") << " | "
       << withFloor(s.gc_train, s.gc_floor_train) << " | " << withFloor(s.gc_test, s.gc_floor_test)
       << " |\n";
  }
  const FloatingGcSummary& gc = outcome.gc;
  if (gc.refused.empty() || gc.validation_segments > 0)
    md << "| the model's own | | | | | | " << withFloor(gc.model_train, gc.floor_train) << " | "
       << withFloor(gc.model_test, gc.floor_test) << " |\n";
  if (!sources.payloads.empty()) {
    const FloatingPayload& first = sources.payloads.front();
    md << "\n## The payload on `" << first.link << "`\n\nIts ten parameters about the origin of `"
       << first.body << "`'s frame, in its axes, "
       << (sources.unloaded.empty()
               ? std::string("from what the model leaves of each set's rows (the model is the "
                             "unloaded robot: its errors enter the payload).")
               : "from the difference of each set's base parameters on these data and on the "
                 "unloaded robot's, `" +
                     sources.unloaded +
                     "` (the robot's parameters unused; a residual scale far above 1 says "
                     "something besides the payload changed between the two).")
       << "\n\n| sensors | mass [kg] | centre of mass [m] | m sd [kg] | residual scale "
          "|\n|---|---|---|---|---|\n";
    for (std::size_t k = 0; k < sources.payloads.size(); ++k) {
      const FloatingPayload& p = sources.payloads[k];
      md << "| " << sensorSetName(outcome.sets[k].base.set) << " | ";
      if (!p.refused.empty()) {
        md << "not estimated: " << p.refused << " | | | |\n";
        continue;
      }
      md << formatNumber(p.phi[0], 4) << " | " << formatNumber(p.phi[1] / p.phi[0], 3) << ", "
         << formatNumber(p.phi[2] / p.phi[0], 3) << ", " << formatNumber(p.phi[3] / p.phi[0], 3)
         << " | " << formatNumber(std::sqrt(p.covariance(0, 0)), 2) << " | "
         << formatNumber(p.residual_scale, 3) << " |\n";
    }
  }
  for (const FloatingSetEstimate& s : outcome.sets) {
    if (!s.refused.empty()) continue;
    md << "\n## " << sensorSetName(s.base.set) << "\n\n" << sensorSetDescription(s.base.set) << ".";
    if (s.combined) md << " The " << combinedLine(*s.combined) << ".";
    md << "\n\n| # | combination | estimate | sd | model |\n|---|---|---|---|---|\n";
    for (int j = 0; j < s.base.base.numBase(); ++j)
      md << "| " << j + 1 << " | `" << s.base.base.expression(j) << "` | "
         << formatNumber(s.fit.beta[j], 6) << " | " << formatNumber(s.fit.sd[j], 3) << " | "
         << formatNumber(s.model_beta[j], 6) << " |\n";
  }
  return md.str();
}

std::string floatingIdentificationSummary(const FloatingModel& model,
                                          const FloatingIdentifyOutcome& outcome,
                                          const FloatingDataSources& sources,
                                          const std::string& dir) {
  std::ostringstream out;
  out << model.name() << " (floating base " << model.baseName() << ", "
      << floatingMotionName(outcome.motion) << ", " << floatingMethodName(outcome.method)
      << "): " << outcome.samples << " samples\n";
  for (const FloatingSetEstimate& s : outcome.sets) {
    out << "  " << sensorSetName(s.base.set) << ": ";
    if (!s.refused.empty()) {
      out << "not estimated: " << s.refused << "\n";
      continue;
    }
    out << s.base.base.numBase() << " base parameters, residual " << percent(s.residual_percent);
    if (!std::isnan(s.validation_percent)) out << ", held out " << percent(s.validation_percent);
    out << ", " << percent(s.model_error_percent) << " from the model (z RMS "
        << formatNumber(s.model_z_rms, 3, "undefined: a residual at round-off gives no sd") << ")";
    if (s.physical)
      out << (s.physical->converged ? ", physically consistent in " : ", NOT CONVERGED after ")
          << s.physical->iterations << " Newton steps";
    if (!std::isnan(s.gc_train) || !std::isnan(s.gc_test))
      out << ", GC error " << withFloor(s.gc_train, s.gc_floor_train) << ", held out "
          << withFloor(s.gc_test, s.gc_floor_test);
    out << "\n";
    if (s.combined) out << "    " << combinedLine(*s.combined) << "\n";
  }
  out << "  " << gcSummaryLine(outcome.gc) << "\n";
  for (std::size_t k = 0; k < sources.payloads.size(); ++k) {
    const FloatingPayload& p = sources.payloads[k];
    out << "  payload on " << p.link << " from " << sensorSetName(outcome.sets[k].base.set) << ": ";
    if (!p.refused.empty())
      out << "not estimated: " << p.refused << "\n";
    else
      out << formatNumber(p.phi[0], 4) << " +- "
          << formatNumber(2 * std::sqrt(p.covariance(0, 0)), 2) << " kg at "
          << formatNumber(p.phi[1] / p.phi[0], 3) << ", " << formatNumber(p.phi[2] / p.phi[0], 3)
          << ", " << formatNumber(p.phi[3] / p.phi[0], 3) << " m"
          << (sources.unloaded.empty() ? std::string()
                                       : " (from the unloaded data; residual scale " +
                                             formatNumber(p.residual_scale, 3) + ")")
          << "\n";
  }
  out << "wrote " << dir << "/floating_identification.json and " << dir
      << "/floating_identification.md\n";
  return out.str();
}

}  // namespace dynid
