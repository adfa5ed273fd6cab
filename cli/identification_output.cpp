#include "cli/identification_output.hpp"

#include <cmath>
#include <sstream>

#include "core/parameters.hpp"

namespace dynid::cli {

using nlohmann::json;

namespace {
json vectorJson(const Eigen::VectorXd& v) {
  json out = json::array();
  for (double x : v) out.push_back(std::isfinite(x) ? json(x) : json(nullptr));
  return out;
}
}  // namespace

std::string formatShort(double x) {
  if (std::isinf(x)) return "inf";
  std::ostringstream s;
  s.precision(4);
  s << x;
  return s.str();
}

void addStructuralOptions(po::options_description& options) {
  options.add_options()("samples", po::value<int>()->default_value(0),
                        "random states for the structural analysis (0: max(100, 5 p / n))")(
      "seed", po::value<std::uint64_t>()->default_value(1), "seed of the random states")(
      "tolerance", po::value<double>()->default_value(0.0),
      "rank tolerance on |R_jj| of the unit-column W (0: 1e-8 max|R_jj|)");
}

BaseParameters structuralBaseParameters(const Model& model, const po::variables_map& vm) {
  const ParameterLayout layout = model.parameterLayout();
  int samples = vm["samples"].as<int>();
  if (samples < 0) throw UsageError("--samples must be >= 0");
  if (samples == 0) samples = std::max(100, 5 * layout.size() / model.numJoints());
  const Observation structural =
      observationFromRandomStates(model, samples, vm["seed"].as<std::uint64_t>());
  return computeBaseParameters(structural.W, standardParameterNames(layout),
                               vm["tolerance"].as<double>(),
                               defaultPreference(layout.num_links, layout.perLink()));
}

json identifiabilityJson(const Model& model, const BaseParameters& base,
                         const po::variables_map& vm) {
  const Eigen::VectorXd theta = model.standardParameters();
  const Eigen::VectorXd beta = base.project(theta);
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
  for (Eigen::Index c = 0; c < N.cols(); ++c) basis.push_back(vectorJson(N.col(c)));
  const Observation check = observationFromRandomStates(model, std::max(100, base.numStandard()),
                                                        vm["seed"].as<std::uint64_t>() + 1);
  return {{"schema_version", kIdentificationSchemaVersion},
          {"robot", model.name},
          {"drives", model.drives_enabled},
          {"offsets", model.offsets_enabled},
          {"num_standard", base.numStandard()},
          {"num_base", base.numBase()},
          {"rank_tolerance", base.tolerance},
          {"smallest_kept_r", numberOrNull(base.smallest_kept)},
          {"largest_dropped_r", base.largest_dropped},
          {"rank_gap", numberOrNull(base.rankGap())},
          {"standard_parameters", base.standard_names},
          {"base_parameters", bases},
          {"unidentifiable", unidentifiable},
          {"regrouped", regrouped},
          {"null_space", {{"parameters", base.standard_names}, {"basis", basis}}},
          {"condition_number", numberOrNull(scaledConditionNumber(base.baseRegressor(check.W)))},
          {"structural",
           {{"method", "column-scaled Householder QR without pivoting (Gautier)"},
            {"random_states", vm["samples"].as<int>()},
            {"seed", vm["seed"].as<std::uint64_t>()}}}};
}

json excitationJson(const BaseParameters& base, const Observation& observation,
                    const std::string& file) {
  const Eigen::MatrixXd W1 = base.baseRegressor(observation.W);
  const Excitation excitation = measureExcitation(W1);
  json per = json::array(), unexcited = json::array();
  for (int j = 0; j < base.numBase(); ++j)
    per.push_back({{"name", base.baseName(j)},
                   {"r_diagonal", excitation.r_diagonal[j]},
                   {"excited", excitation.r_diagonal[j] > excitation.tolerance}});
  for (int j : excitation.unexcited) unexcited.push_back(base.baseName(j));
  // The rank the data reach on the full standard set (may exceed nothing: at most num_base).
  return {{"file", file},
          {"samples", observation.num_samples},
          {"rank", excitation.rank},
          {"structural_rank", base.numBase()},
          {"unexcited", unexcited},
          {"excitation", per},
          {"condition_number", numberOrNull(scaledConditionNumber(W1))}};
}

std::string identifiabilityMarkdown(const json& r) {
  std::ostringstream md;
  md << "# Identifiability of " << r["robot"].get<std::string>() << "\n\n";
  md << "- Standard parameters: " << r["num_standard"] << " (drives "
     << (r["drives"].get<bool>() ? "on" : "off") << ")\n";
  md << "- Base parameters (structural rank): **" << r["num_base"] << "**\n";
  md << "- Rank gap (smallest kept / largest dropped |R_jj|): "
     << (r["rank_gap"].is_null() ? "inf" : formatShort(r["rank_gap"].get<double>())) << "\n";
  md << "- Condition number of the column-scaled base regressor on random states: "
     << (r["condition_number"].is_null() ? "inf" : formatShort(r["condition_number"].get<double>()))
     << "\n\n";
  md << "## Base parameters\n\nEach is identifiable; the standard parameters after the first are "
        "regrouped into it and cannot be told apart.\n\n| # | name | combination | model value |\n"
        "|---|---|---|---|\n";
  int index = 1;
  for (const auto& b : r["base_parameters"])
    md << "| " << index++ << " | " << b["name"].get<std::string>() << " | `"
       << b["expression"].get<std::string>() << "` | "
       << formatShort(b["model_value"].get<double>()) << " |\n";
  md << "\n## Never affect the torques\n\n";
  if (r["unidentifiable"].empty()) md << "(none)\n";
  for (const auto& name : r["unidentifiable"]) md << "`" << name.get<std::string>() << "` ";
  md << "\n\n## Identifiable only in combination\n\n";
  if (r["regrouped"].empty()) md << "(none)\n";
  for (const auto& name : r["regrouped"]) md << "`" << name.get<std::string>() << "` ";
  md << "\n";
  if (r.contains("data")) {
    const json& d = r["data"];
    md << "\n## Excitation by " << d["file"].get<std::string>()
       << "\n\n- Rank reached: " << d["rank"] << " of " << d["structural_rank"]
       << "\n- Condition number: "
       << (d["condition_number"].is_null() ? "inf"
                                           : formatShort(d["condition_number"].get<double>()))
       << "\n- Not excited: ";
    if (d["unexcited"].empty()) md << "(none)";
    for (const auto& name : d["unexcited"]) md << "`" << name.get<std::string>() << "` ";
    md << "\n\n| base parameter | scaled abs(R_jj) |\n|---|---|\n";
    for (const auto& e : d["excitation"])
      md << "| " << e["name"].get<std::string>() << " | "
         << formatShort(e["r_diagonal"].get<double>())
         << (e["excited"].get<bool>() ? "" : " (not excited)") << " |\n";
  }
  return md.str();
}

json estimateJson(const Model& model, const BaseParameters& base, const BaseEstimate& estimate,
                  const std::string& data_file) {
  const Eigen::VectorXd prior = model.standardParameters();
  const Eigen::VectorXd model_beta = base.project(prior);
  json params = json::array();
  for (int j = 0; j < base.numBase(); ++j)
    params.push_back(
        {{"name", base.baseName(j)},
         {"expression", base.expression(j)},
         {"estimate", estimate.beta[j]},
         {"std_dev", estimate.std_dev[j]},
         {"relative_std_dev_percent", numberOrNull(estimate.relative_std_dev_percent[j])},
         {"model_value", model_beta[j]}});
  const Eigen::VectorXd standard = base.standardFromBase(estimate.beta, prior);
  json standard_json = json::object();
  for (int k = 0; k < base.numStandard(); ++k) standard_json[base.standard_names[k]] = standard[k];
  return {{"schema_version", kIdentificationSchemaVersion},
          {"robot", model.name},
          {"drives", model.drives_enabled},
          {"method", leastSquaresMethodName(estimate.method)},
          {"data", {{"file", data_file}, {"samples", estimate.num_samples}}},
          {"num_base", base.numBase()},
          {"base_parameters", params},
          {"condition_number", numberOrNull(estimate.condition_number)},
          {"joint_sigma", vectorJson(estimate.joint_sigma)},
          {"residual_rms", vectorJson(estimate.residual_rms)},
          {"standard_estimate",
           {{"note", "base parameters fixed to the estimate, the rest from the robot model"},
            {"values", standard_json}}}};
}

json validationJson(const Validation& validation, const std::string& file) {
  return {{"file", file},
          {"samples", validation.num_samples},
          {"torque_rms", vectorJson(validation.torque_rms)},
          {"normalised_rms", vectorJson(validation.normalised_rms)}};
}

std::string estimateMarkdown(const json& r) {
  std::ostringstream md;
  md << "# " << r["method"].get<std::string>() << " estimate for " << r["robot"].get<std::string>()
     << "\n\nData: " << r["data"]["file"].get<std::string>() << " (" << r["data"]["samples"]
     << " samples). Condition number of the scaled base regressor: "
     << (r["condition_number"].is_null() ? "inf" : formatShort(r["condition_number"].get<double>()))
     << ".\n\n| base parameter | estimate | std. dev. | %σ | model value "
        "|\n|---|---|---|---|---|\n";
  for (const auto& p : r["base_parameters"])
    md << "| `" << p["expression"].get<std::string>() << "` | "
       << formatShort(p["estimate"].get<double>()) << " | "
       << formatShort(p["std_dev"].get<double>()) << " | "
       << (p["relative_std_dev_percent"].is_null()
               ? "inf"
               : formatShort(p["relative_std_dev_percent"].get<double>()))
       << " | " << formatShort(p["model_value"].get<double>()) << " |\n";
  md << "\n| joint | residual RMS [N m] |";
  const bool validated = r.contains("validation");
  if (validated) md << " held-out RMS [N m] | normalised |";
  md << "\n|---|---|" << (validated ? "---|---|" : "") << "\n";
  for (std::size_t j = 0; j < r["residual_rms"].size(); ++j) {
    md << "| " << j + 1 << " | " << formatShort(r["residual_rms"][j].get<double>()) << " |";
    if (validated) {
      const json& v = r["validation"];
      md << " " << formatShort(v["torque_rms"][j].get<double>()) << " | "
         << (v["normalised_rms"][j].is_null() ? "inf"
                                              : formatShort(v["normalised_rms"][j].get<double>()))
         << " |";
    }
    md << "\n";
  }
  return md.str();
}

}  // namespace dynid::cli
