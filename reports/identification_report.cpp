#include "reports/identification_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "analysis/records/document.hpp"
#include "analysis/records/search_record.hpp"
#include "analysis/runs/arm.hpp"
#include "core/format.hpp"
#include "core/parameters.hpp"
#include "data/io.hpp"
#include "data/json_number.hpp"
#include "data/model_json.hpp"
#include "reports/model_report.hpp"
#include "reports/prediction_report.hpp"

namespace dynid {

using nlohmann::json;

namespace {
/// The smallest unit-column |R_jj| kept (kept) or the largest dropped among acting columns.
double keptR(const BaseParameters& base, bool kept) {
  double out = kept ? std::numeric_limits<double>::infinity() : 0.0;
  for (int j : kept ? base.independent : base.dependent)
    if (base.significance.size() == 0 || base.significance[j] > 0.0)
      out = kept ? std::min(out, base.r_diagonal[j]) : std::max(out, base.r_diagonal[j]);
  return out;
}

json excitationJson(const BaseParameters& base, const DataExcitation& data) {
  const Excitation& excitation = data.excitation;
  json per = json::array(), unexcited = json::array();
  for (int j = 0; j < base.numBase(); ++j)
    per.push_back({{"name", base.baseName(j)},
                   {"r_diagonal", excitation.r_diagonal[j]},
                   {"excited", excitation.r_diagonal[j] > excitation.tolerance}});
  for (int j : excitation.unexcited) unexcited.push_back(base.baseName(j));
  // The rank the data reach on the full standard set (may exceed nothing: at most num_base).
  return {{"file", data.file},
          {"samples", data.samples},
          {"rank", excitation.rank},
          {"structural_rank", base.numBase()},
          {"unexcited", unexcited},
          {"excitation", per},
          {"condition_number", numberOrNull(data.condition_number)}};
}
}  // namespace

json identifiabilityJson(const Model& model, const IdentifiabilityOutcome& outcome) {
  const BaseParameters& base = outcome.base;
  const Eigen::VectorXd& beta = outcome.model_beta;
  json bases = json::array();
  for (int j = 0; j < base.numBase(); ++j) {
    json coefficients = json::object();
    for (const auto& [name, c] : base.combination(j)) coefficients[name] = c;
    bases.push_back({{"name", base.baseName(j)},
                     {"expression", base.expression(j)},
                     {"coefficients", coefficients},
                     {"model_value", beta[j]}});
  }
  json unidentifiable = json::array(), regrouped = json::array();
  for (int k : base.zero_columns) unidentifiable.push_back(base.standard_names[k]);
  for (int k : base.dependent)
    if (std::find(base.zero_columns.begin(), base.zero_columns.end(), k) == base.zero_columns.end())
      regrouped.push_back(base.standard_names[k]);
  const Eigen::MatrixXd N = base.nullSpace();
  json basis = json::array();
  for (Eigen::Index c = 0; c < N.cols(); ++c) basis.push_back(numbersOrNull(N.col(c)));
  json report = {{"schema_version", kIdentifiabilityDocument.schema_version},
                 {"kind", kIdentifiabilityDocument.kind},
                 {"robot", model.name},
                 {"drives", model.driveTerms().any()},
                 {"drive_terms", driveTermsKeys(model.driveTerms())},
                 {"num_standard", base.numStandard()},
                 {"num_base", base.numBase()},
                 {"rank_tolerance", base.tolerance},
                 {"smallest_kept_r", numberOrNull(keptR(base, true))},
                 {"largest_dropped_r", keptR(base, false)},
                 {"rank_gap", numberOrNull(base.rankGap())},
                 {"standard_parameters", base.standard_names},
                 {"base_parameters", bases},
                 {"unidentifiable", unidentifiable},
                 {"regrouped", regrouped},
                 {"null_space", {{"parameters", base.standard_names}, {"basis", basis}}},
                 {"condition_number", numberOrNull(outcome.condition_number)},
                 {"structural",
                  {{"method", "column-scaled Householder QR without pivoting (Gautier)"},
                   {"random_states", outcome.structural.samples},
                   {"seed", outcome.structural.seed}}}};
  if (outcome.data) report["data"] = excitationJson(base, *outcome.data);
  return report;
}

std::string identifiabilityMarkdown(const Model& model, const IdentifiabilityOutcome& outcome) {
  const BaseParameters& base = outcome.base;
  const auto four = [](double x) { return std::isfinite(x) ? formatNumber(x, 4) : "inf"; };
  std::ostringstream md;
  md << "# Identifiability of " << model.name << "\n\n";
  std::string terms;
  for (const std::string& t : driveTermsKeys(model.driveTerms())) {
    if (!terms.empty()) terms += ',';
    terms += t;
  }
  md << "- Standard parameters: " << base.numStandard() << " (drive terms "
     << (terms.empty() ? "none" : terms) << ")\n";
  md << "- Base parameters (structural rank): **" << base.numBase() << "**\n";
  md << "- Rank gap (smallest kept / largest dropped |R_jj|): " << four(base.rankGap()) << "\n";
  md << "- Condition number of the column-scaled base regressor on random states: "
     << four(outcome.condition_number) << "\n\n";
  md << "## Base parameters\n\nEach is identifiable; the standard parameters after the first are "
        "regrouped into it and cannot be told apart.\n\n| # | name | combination | model value |\n"
        "|---|---|---|---|\n";
  for (int j = 0; j < base.numBase(); ++j)
    md << "| " << j + 1 << " | " << base.baseName(j) << " | `" << base.expression(j) << "` | "
       << formatNumber(outcome.model_beta[j], 4) << " |\n";
  md << "\n## Never affect the torques\n\n";
  if (base.zero_columns.empty()) md << "(none)\n";
  for (int k : base.zero_columns) md << "`" << base.standard_names[k] << "` ";
  md << "\n\n## Identifiable only in combination\n\n";
  std::vector<std::string> regrouped;
  for (int k : base.dependent)
    if (std::find(base.zero_columns.begin(), base.zero_columns.end(), k) == base.zero_columns.end())
      regrouped.push_back(base.standard_names[k]);
  if (regrouped.empty()) md << "(none)\n";
  for (const std::string& name : regrouped) md << "`" << name << "` ";
  md << "\n";
  if (outcome.data) {
    const DataExcitation& d = *outcome.data;
    const Excitation& e = d.excitation;
    md << "\n## Excitation by " << d.file << "\n\n- Rank reached: " << e.rank << " of "
       << base.numBase() << "\n- Condition number: " << four(d.condition_number)
       << "\n- Not excited: ";
    if (e.unexcited.empty()) md << "(none)";
    for (int j : e.unexcited) md << "`" << base.baseName(j) << "` ";
    md << "\n\n| base parameter | scaled abs(R_jj) |\n|---|---|\n";
    for (int j = 0; j < base.numBase(); ++j)
      md << "| " << base.baseName(j) << " | " << formatNumber(e.r_diagonal[j], 4)
         << (e.r_diagonal[j] > e.tolerance ? "" : " (not excited)") << " |\n";
  }
  return md.str();
}

namespace {
/// kinematicsSignature as rows of 15 numbers (the frames at q = 0 and the axes).
json kinematicsJson(const Model& model) {
  const Eigen::MatrixXd k = kinematicsSignature(model);
  json rows = json::array();
  for (Eigen::Index i = 0; i < k.rows(); ++i) rows.push_back(numbersOrNull(k.row(i).transpose()));
  return rows;
}
}  // namespace

json combinedHistoryJson(const CombinedResult& r) {
  json out = json::array();
  for (const CombinedIteration& it : r.history)
    out.push_back({{"iteration", it.iteration},
                   {"cost", numberOrNull(it.cost)},
                   {"torque_term", numberOrNull(it.torque)},
                   {"gc_error", numberOrNull(it.gc)},
                   {"seconds", it.seconds}});
  return out;
}

namespace {
/// estimate.json's base_covariance: each base parameter's regressor column and the matrix.
json baseCovarianceJson(const IdentifyOutcome& outcome) {
  const BaseParameters& base = outcome.base;
  const BaseEstimate& estimate = outcome.result.estimate;
  json independent = json::array(), matrix = json::array();
  for (int j = 0; j < base.numBase(); ++j) {
    independent.push_back(base.standard_names[static_cast<std::size_t>(base.independent[j])]);
    matrix.push_back(numbersOrNull(estimate.covariance.row(j).transpose()));
  }
  const CovarianceSummary& policy = outcome.result.covariance;
  json policy_json = {{"name", policy.policy}};
  if (policy.policy == "hac") {
    policy_json["batch"] = policy.batch;
    policy_json["inflation"] = numberOrNull(policy.inflation);
    policy_json["autocorrelation"] = policy.autocorrelation;
    policy_json["note"] =
        "heteroscedasticity and autocorrelation consistent over batches of `batch` consecutive "
        "samples: sum_b H^-1 (I - H_b H^-1)^-1/2 s_b s_b^T (...)^T with s_b a batch's scores and "
        "H_b its share of the normal matrix H (the bias-reduced cluster-robust estimator, CR2); "
        "`batch`: four times the first lag 1, 2, 4, ... at which the residuals' mean "
        "autocorrelation falls below 0.05, at least the samples over 256; `inflation`: the median "
        "standard deviation over the white covariance's";
  } else {
    policy_json["note"] = "sigma^2 (W1^T W1)^-1: the residuals taken as white";
  }
  return {
      {"note", outcome.result.pc
                   ? "covariance at the physically consistent estimate, constraints inactive: its "
                     "torque band is that of the unconstrained estimate at the same point, "
                     "conservative where the constraints or the prior bind"
                   : "covariance of the base parameters, in base_parameters' order; each column of "
                     "the base regressor is the standard parameter named in `columns`"},
      {"policy", policy_json},
      {"columns", independent},
      {"matrix", matrix}};
}
}  // namespace

namespace {

/// estimate.json's "combined": the combined estimate's two criteria against pc's.
json combinedJson(const CombinedSummary& summary) {
  const CombinedSummary* c = &summary;
  return {
      {"termination", c->detail.termination},
      {"moved", c->detail.moved},
      {"iterations", c->detail.iterations},
      {"seconds", c->detail.seconds},
      {"gc_weight", c->detail.gc_weight},
      {"gc_noise_floor", c->detail.gc_floor},
      {"segments_train", c->train_segments},
      {"segments_test", c->test_segments},
      {"gc_error_train",
       {{"pc", numberOrNull(c->gc_train_pc)}, {"combined", numberOrNull(c->gc_train)}}},
      {"gc_error_test",
       {{"pc", numberOrNull(c->gc_test_pc)}, {"combined", numberOrNull(c->gc_test)}}},
      {"torque_relative_error_pc",
       {{"train", numberOrNull(c->torque_train_pc)}, {"test", numberOrNull(c->torque_test_pc)}}},
      {"cost_history", combinedHistoryJson(c->detail)}};
}

/// estimate.json's "front" (`front_weights`): each point's weight and errors, and the choice.
json frontJson(const IdentifyFront& front) {
  json points = json::array();
  for (const IdentifyFrontPoint& p : front.points)
    points.push_back({{"weight", p.weight},
                      {"torque_relative_error_train", numberOrNull(p.torque_train)},
                      {"torque_relative_error_test", numberOrNull(p.test.torque)},
                      {"gc_error_train", numberOrNull(p.gc_train)},
                      {"gc_error_test", numberOrNull(p.test.gc)},
                      {"gc_noise_floor_test", numberOrNull(p.test.gc_floor)},
                      {"physically_consistent", p.test.consistent},
                      {"iterations", p.iterations},
                      {"seconds", p.seconds},
                      {"note", p.note}});
  const FrontChoice& c = front.choice;
  return {{"tolerance", front.tolerance},
          {"points", points},
          {"chosen_weight", front.points[c.index].weight},
          {"best_torque_weight", front.points[c.best_torque].weight},
          {"torque_bound", numberOrNull(c.torque_bound)},
          {"at_noise_floor", c.at_floor},
          {"rule",
           "among the points whose held-out torque error is within (1 + tolerance) of the least "
           "of theirs, the least held-out GC error above its noise floor (within 10 % of the "
           "floor counts as at it); at the floor, the least held-out torque error"}};
}

/// estimate.json's "torque_source" when the torques were motor currents (dynid prepare
/// --current): the constants every parameter scales with, which monitor compares with the ones it
/// is given for a recording; null otherwise.
json torqueSourceJson(const PreparationFound& preparation) {
  const auto& record = preparation.record;
  if (preparation.present && record && !record->torque_constants.empty() &&
      std::all_of(record->torque_constants.begin(), record->torque_constants.end(),
                  [](double k) { return std::isfinite(k) && k != 0.0; }) &&
      std::all_of(record->gear_ratios.begin(), record->gear_ratios.end(),
                  [](double g) { return std::isfinite(g) && g != 0.0; }))
    return {{"kind", "current"},
            {"torque_constants", record->torque_constants},
            {"gear_ratios", record->gear_ratios}};
  return nullptr;
}

/// estimate.json's fit_rows: the rows per joint, why some were left out, the filter reproduced.
json fitRowsJson(const IdentifyOutcome& o) {
  const BaseEstimate& e = o.result.estimate;
  json filter = nullptr;
  if (o.torque_filter.active() && o.filter_reach > 0)
    filter = {{"kind", "Butterworth low-pass, zero phase (forward-backward)"},
              {"order", o.torque_filter.order},
              {"cutoff_hz", o.torque_filter.cutoff},
              {"rate_hz", o.torque_filter.rate},
              {"reach_samples", o.filter_reach},
              {"reach_share", kFilterReachShare}};
  return {{"rows", numbersOrNull(e.fitted_rows)},
          {"samples", e.num_samples},
          {"torque_filter", filter},
          {"torque_filter_source", o.torque_filter_source},
          {"rule",
           "a joint's row is left out where the joint is at rest (|dq| <= its rest velocity) and "
           "the model has friction that needs sign(dq): its static friction there is unknown. "
           "With torque_filter, the friction columns that need sign(dq) are that filter applied "
           "to their values (parallel filtering), and a row is also left out within "
           "reach_samples of a resting sample, beyond which the filter's impulse response holds "
           "reach_share of its absolute sum"}};
}

}  // namespace

std::string fitRowsLine(const IdentifyOutcome& o) {
  const BaseEstimate& e = o.result.estimate;
  const bool filtered = o.torque_filter.active() && o.filter_reach > 0;
  const Eigen::Index n = e.fitted_rows.size();
  const bool left_out = n > 0 && e.fitted_rows.minCoeff() < e.num_samples;
  if (!filtered && !left_out) return "";
  std::string out = "rows fitted per joint:";
  for (Eigen::Index j = 0; j < n; ++j)
    out.append(" ").append(std::to_string(static_cast<long long>(e.fitted_rows[j])));
  out += " of " + std::to_string(e.num_samples) +
         " (a joint at rest has unknown static friction: its row is left out";
  if (filtered)
    out += ", and within " + std::to_string(o.filter_reach) +
           " samples of rest, the reach of the torque's filter); the friction columns that need "
           "sign(dq) through that filter, " +
           o.torque_filter.describe() + " (" + o.torque_filter_source + ")";
  else
    out += ")";
  return out;
}

std::string filteringClause(const IdentifyOutcome& o) {
  if (o.torque_filter.active() && o.filter_reach > 0)
    return "not the torque filter's artefact: the fit reproduces its low-pass (" +
           o.torque_filter.describe() + ") on the friction columns";
  if (!o.preparation.present && !o.torque_filter.active())
    return "if the torque was low-pass filtered before dynid, the filter spreads each reversal's "
           "step, which reads as missing friction: `torque_filter` (its cutoff and order) makes "
           "the fit reproduce it (compare the notes)";
  return "";
}

/// data: the training file (or the summaries) and its samples; from summaries, their logs.
json dataJson(const IdentifyOutcome& o, long long samples) {
  json out = {{"file", o.data_file}, {"samples", samples}};
  if (o.summary_sources.empty()) return out;
  json sources = json::array();
  for (const SummarySource& s : o.summary_sources)
    sources.push_back({{"file", s.file},
                       {"sha256", s.sha256},
                       {"samples", s.samples},
                       {"torque_filter", s.torque_filter.active() ? json(s.torque_filter.describe())
                                                                  : json(nullptr)}});
  out["sources"] = std::move(sources);
  return out;
}

json estimateJson(const Model& model, const IdentifyOutcome& outcome) {
  const BaseParameters& base = outcome.base;
  const BaseEstimate& estimate = outcome.result.estimate;
  const Eigen::VectorXd& model_beta = outcome.model_beta;
  json params = json::array();
  for (int j = 0; j < base.numBase(); ++j)
    params.push_back(
        {{"name", base.baseName(j)},
         {"expression", base.expression(j)},
         {"estimate", estimate.beta[j]},
         {"std_dev", estimate.std_dev[j]},
         {"relative_std_dev_percent", numberOrNull(estimate.relative_std_dev_percent[j])},
         {"model_value", model_beta[j]}});
  const Eigen::VectorXd& standard = outcome.result.standard;
  json standard_json = json::object();
  for (int k = 0; k < base.numStandard(); ++k) standard_json[base.standard_names[k]] = standard[k];
  json report = {
      {"schema_version", kEstimateDocument.schema_version},
      {"kind", kEstimateDocument.kind},
      {"robot", model.name},
      {"robot_spec", outcome.robot_spec},
      {"kinematics", kinematicsJson(model)},
      {"model", json::parse(modelToJson(model))},
      {"model_source", modelSourceJson(ModelSource{
                           outcome.robot_spec,
                           outcome.robot_sha256.empty()
                               ? ""
                               : std::filesystem::path(outcome.robot_spec).filename().string(),
                           outcome.robot_sha256})},
      {"drives", model.driveTerms().any()},
      {"drive_terms", driveTermsKeys(model.driveTerms())},
      {"method", methodName(outcome.method)},
      {"data", dataJson(outcome, estimate.num_samples)},
      {"num_base", base.numBase()},
      {"base_parameters", params},
      {"condition_number", numberOrNull(estimate.condition_number)},
      {"condition_number_unscaled", numberOrNull(estimate.condition_number_unscaled)},
      {"joint_sigma", numbersOrNull(estimate.joint_sigma)},
      {"residual_rms", numbersOrNull(estimate.residual_rms)},
      {"measured_rms", numbersOrNull(estimate.measured_rms)},
      {"relative_error", numberOrNull(estimate.relative_error)},
      {"joint_relative_error", numbersOrNull(estimate.joint_relative_error)},
      {"standard_estimate",
       {{"note", "base parameters fixed to the estimate, the rest from the robot model"},
        {"values", standard_json}}}};
  // The base covariance with each base parameter's column: predict's torque bands.
  if (estimate.covariance.rows() == base.numBase() && estimate.covariance.allFinite())
    report["base_covariance"] = baseCovarianceJson(outcome);
  if (const auto& pc = outcome.result.pc) {
    report["standard_estimate"]["note"] =
        "physically consistent on every link (positive definite pseudo-inertias)";
    report["physically_consistent"] = {
        {"termination", pc->termination},
        {"solution_usable", pc->usable},
        {"iterations", pc->iterations},
        {"prior_weight", outcome.prior_weight},
        {"ols_lift_inconsistent_links", outcome.pc_inconsistent_links},
        {"drive_parameters_at_bound", pc->at_bound},
        {"cost_history", pc->cost_history}};
  }
  if (const auto& c = outcome.combined) report["combined"] = combinedJson(*c);
  if (const auto& front = outcome.front) report["front"] = frontJson(*front);
  if (const auto& back = outcome.write_back)
    report["write_back"] = {
        {"unseen_directions", back->unseen_directions},
        {"note",
         "the written URDF and JSON carry the standard estimate; the directions the data cannot "
         "see come from the input model (the prior)"}};
  if (outcome.reversals.samples > 0) report["reversals"] = reversalsJson(outcome.reversals);
  if (!outcome.rest.empty()) report["rest_velocity"] = restVelocityJson(outcome.rest);
  if (estimate.fitted_rows.size() > 0) report["fit_rows"] = fitRowsJson(outcome);
  if (const auto& v = outcome.validation)
    report["validation"] = {{"file", outcome.validate_file},
                            {"samples", v->num_samples},
                            {"residual_rms", numbersOrNull(v->torque_rms)},
                            {"joint_relative_error", numbersOrNull(v->normalised_rms)},
                            {"relative_error", numberOrNull(v->relative_error)}};
  if (outcome.validate_fit && outcome.validate_fit->rest.samples.size() > 0)
    report["validation"]["at_rest"] = atRestJson(outcome.validate_fit->rest);
  if (const auto& raw = outcome.raw_validation)
    report["validation"]["raw_measurement"] =
        rawValidationJson(*raw, outcome.validate_raw_file, outcome.raw_skipped);
  if (json source = torqueSourceJson(outcome.preparation); !source.is_null())
    report["torque_source"] = std::move(source);
  return report;
}

}  // namespace dynid

namespace dynid {

std::string identifiabilitySummary(const Model& model, const IdentifiabilityOutcome& outcome,
                                   const std::string& dir) {
  const BaseParameters& base = outcome.base;
  std::ostringstream out;
  out << model.name << ": " << base.numStandard() << " standard parameters, " << base.numBase()
      << " base parameters (rank gap " << formatNumber(base.rankGap(), 4) << "), "
      << base.zero_columns.size() << " never affect the torques";
  if (outcome.data) out << "; the data reach rank " << outcome.data->excitation.rank;
  out << "\nwrote " << dir << "/identifiability.json and " << dir << "/identifiability.md\n";
  return out.str();
}

std::string covarianceLine(const CovarianceSummary& c) {
  if (c.policy != "hac")
    return "intervals: the white covariance sigma^2 (W1^T W1)^-1, which takes the residuals as "
           "uncorrelated";
  std::string out = "intervals: robust to correlated residuals, over " + std::to_string(c.batch) +
                    "-sample batches";
  if (!c.autocorrelation.empty()) {
    out += " (the residuals' autocorrelation " + formatNumber(c.autocorrelation.front(), 2) +
           " at lag 1";
    const std::size_t last = c.autocorrelation.size() - 1;
    if (last > 0)
      out +=
          ", " + formatNumber(c.autocorrelation[last], 2) + " at lag " + std::to_string(1 << last);
    out += ")";
  }
  return out + "; standard deviations " + formatNumber(c.inflation, 3) +
         " times the white covariance's (median)";
}

std::string estimateSummary(const Model& model, const IdentifyOutcome& outcome,
                            const std::string& dir) {
  const BaseEstimate& estimate = outcome.result.estimate;
  std::ostringstream out;
  out << model.name << ": " << methodName(outcome.method) << " estimate of "
      << outcome.base.numBase() << " base parameters from " << estimate.num_samples
      << " samples; condition number " << formatNumber(estimate.condition_number_unscaled, 4)
      << " (unscaled), " << formatNumber(estimate.condition_number, 4) << " (unit columns)\n"
      << "  relative torque error " << formatNumber(100.0 * estimate.relative_error, 4)
      << " %; per joint RMS [N m]:";
  for (Eigen::Index j = 0; j < estimate.residual_rms.size(); ++j)
    out << " " << formatNumber(estimate.residual_rms[j], 4);
  if (const auto& v = outcome.validation) {
    out << "\n  held out: relative torque error " << formatNumber(100.0 * v->relative_error, 4)
        << " %; per joint RMS [N m]:";
    for (Eigen::Index j = 0; j < v->torque_rms.size(); ++j)
      out << " " << formatNumber(v->torque_rms[j], 4);
    if (const auto& raw = outcome.raw_validation)
      out << "\n  " << rawValidationLine(*raw, outcome.raw_skipped);
    if (outcome.validate_fit)
      if (const std::string line = atRestLine(outcome.validate_fit->rest); !line.empty())
        out << "\n  held out " << line;
  }
  if (const auto& f = outcome.front) {
    const IdentifyFrontPoint& chosen = f->points[f->choice.index];
    out << "\n  the front: " << f->points.size()
        << " points (w = " << formatNumber(f->points.front().weight, 3) << " to "
        << formatNumber(f->points.back().weight, 3)
        << "); chosen w = " << formatNumber(chosen.weight, 3) << ": held-out GC error "
        << formatNumber(chosen.test.gc, 4) << " (its noise floor "
        << formatNumber(chosen.test.gc_floor, 4) << "), "
        << (f->choice.at_floor ? "every rival at its floor too: the least torque error"
                               : "the least above its floor")
        << " among the points within " << formatNumber(100.0 * f->tolerance, 3)
        << " % of the least held-out torque error";
  }
  if (const std::string line = restVelocityLine(outcome.rest); !line.empty()) out << "\n  " << line;
  if (const std::string line = fitRowsLine(outcome); !line.empty()) out << "\n  " << line;
  out << "\n  " << covarianceLine(outcome.result.covariance);
  if (const std::string note =
          reversalNote(model.driveTerms(), outcome.reversals, filteringClause(outcome));
      !note.empty())
    out << "\nnote: " << note;
  out << "\nwrote " << dir << "/estimate.json, " << dir << "/report.md and " << dir
      << "/report.html\n";
  return out.str();
}

std::string writeBackJsonPath(const std::string& urdf_path) {
  return std::filesystem::path(urdf_path).replace_extension(".dynid.json").string();
}

std::string writeWriteBack(const std::string& urdf_path, const WriteBack& back) {
  const std::string json_path = writeBackJsonPath(urdf_path);
  // A new directory (--out's, not made yet) is made, and removed again, empty, when the write
  // fails: nothing is left behind.
  const std::filesystem::path parent = std::filesystem::path(urdf_path).parent_path();
  std::error_code error;
  const bool make = !parent.empty() && !std::filesystem::exists(parent, error);
  if (make) std::filesystem::create_directories(parent);
  try {
    // Both written whole first, then both renamed with signals held: both or neither, and a
    // failure deletes nothing (the input URDF is refused as a target: InputFileGuard).
    AtomicWriter urdf(urdf_path), json(json_path);
    urdf.write(back.urdf);
    json.write(back.model_json);
    urdf.stage();
    json.stage();
    const PublishWindow window;
    urdf.commit();
    json.commit();
  } catch (...) {
    if (make) std::filesystem::remove(parent, error);  // only when still empty
    throw;
  }
  std::string out = "wrote " + urdf_path +
                    " (mass, centre of mass, inertia; <dynamics> Fv, Fc where the "
                    "model has them) and " +
                    json_path + " (every parameter); the " +
                    std::to_string(back.unseen_directions) +
                    " directions the data cannot see come from the input model\n";
  if (!back.not_in_urdf.empty()) {
    const std::size_t shown = std::min<std::size_t>(back.not_in_urdf.size(), 8);
    std::string list;
    for (std::size_t k = 0; k < shown; ++k) list += (k == 0 ? "" : ", ") + back.not_in_urdf[k];
    if (shown < back.not_in_urdf.size())
      list += " and " + std::to_string(back.not_in_urdf.size() - shown) + " more";
    out +=
        "note: URDF has no place for rotor inertias, offsets or other drive terms: " + urdf_path +
        " goes without " + list + ", which its torques then lack; " + json_path +
        " carries them (dynid --robot, or add them in the controller)\n";
  }
  return out;
}

std::string solverWarning(const IdentifyOutcome& outcome) {
  if (!outcome.result.pc) return "";
  const PhysicalEstimate& pc = *outcome.result.pc;
  if (pc.termination.rfind("CONVERGENCE", 0) == 0) return "";
  return "the physically consistent solver stopped before converging after " +
         std::to_string(pc.iterations) + " iterations (" + pc.termination +
         "): the estimate is its last iterate";
}

}  // namespace dynid
