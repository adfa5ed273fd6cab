// dynid identify: least-squares estimate of the base parameters from a torque dataset.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/identification_output.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/robots.hpp"
#include "identifiability/physically_consistent.hpp"

namespace dynid::cli {

int runIdentify(const std::vector<std::string>& args) {
  po::options_description options("dynid identify");
  addRobotOptions(options);
  addStructuralOptions(options);
  options.add_options()("method", po::value<std::string>()->default_value("ols"),
                        "ols (ordinary), wls (weighted per joint, Gautier) or pc (physically "
                        "consistent: log-Cholesky least squares from OLS)")(
      "prior", po::value<std::string>(),
      "pc: prior model (robot spec; default: the robot's own parameters)")(
      "prior-weight", po::value<double>()->default_value(0.0),
      "pc: weight of the pull toward the prior (0: none)")(
      "data", po::value<std::string>()->required(), "training dataset CSV")(
      "validate", po::value<std::string>(), "held-out dataset CSV: torque RMS per joint")(
      "out", po::value<std::string>()->required(), "output directory (estimate.json, estimate.md)");
  po::variables_map vm;
  const std::string usage =
      "dynid identify --method ols|wls|pc --robot R [--drives] --data train.csv [--validate "
      "test.csv] "
      "--out DIR";
  if (!parseCommandLine(args, options, usage, vm)) return kExitOk;
  const std::string method_name = vm["method"].as<std::string>();
  const bool physical = method_name == "pc";
  LeastSquaresMethod method = LeastSquaresMethod::kOrdinary;
  if (!physical) {
    try {
      method = parseLeastSquaresMethod(method_name);
    } catch (const InputError& e) {
      throw UsageError("--method must be ols, wls or pc, not '" + method_name + "'");
    }
  }
  const double prior_weight = vm["prior-weight"].as<double>();
  if (!(prior_weight >= 0.0) || !std::isfinite(prior_weight))
    throw UsageError("--prior-weight must be finite and >= 0");
  const Model model = loadRobotFromOptions(vm);
  const std::string data_file = vm["data"].as<std::string>();
  const Observation train =
      observationFromTrajectory(model, readDatasetCsv(data_file, model.numJoints()));
  const BaseParameters base = structuralBaseParameters(model, vm);
  BaseEstimate estimate;
  nlohmann::json physical_json;
  Eigen::VectorXd physical_theta;
  if (physical) {
    Model prior_model = model;
    if (vm.count("prior")) {
      prior_model = loadRobot(vm["prior"].as<std::string>(),
                              {vm["drives"].as<bool>(), vm["strict"].as<bool>()});
      if (prior_model.parameterLayout().size() != model.parameterLayout().size())
        throw InputError("the prior model has another parameter layout than the robot");
    }
    PhysicalOptions options;
    options.prior_weight = prior_weight;
    const PhysicalEstimate pc =
        estimatePhysicallyConsistent(base, train, prior_model.standardParameters(), options);
    // The base estimate's fields from the physically consistent solution.
    estimate = pc.ols;
    estimate.beta = pc.beta;
    estimate.covariance = pc.covariance;
    estimate.std_dev = pc.std_dev;
    estimate.residual_rms = pc.residual_rms;
    for (int j = 0; j < base.numBase(); ++j)
      estimate.relative_std_dev_percent[j] = pc.beta[j] != 0.0
                                                 ? 100.0 * pc.std_dev[j] / std::abs(pc.beta[j])
                                                 : std::numeric_limits<double>::infinity();
    physical_theta = pc.theta;
    std::vector<std::string> inconsistent;
    for (int i : pc.inconsistent_links) inconsistent.push_back(model.link_names[i]);
    physical_json = {{"termination", pc.termination},
                     {"solution_usable", pc.usable},
                     {"iterations", pc.iterations},
                     {"prior_weight", prior_weight},
                     {"ols_lift_inconsistent_links", inconsistent},
                     {"drive_parameters_at_bound", pc.at_bound},
                     {"cost_history", pc.cost_history}};
  } else {
    estimate = estimateBaseParameters(base, train, method);
  }
  nlohmann::json report = estimateJson(model, base, estimate, data_file);
  if (physical) {
    report["method"] = "pc";
    nlohmann::json values = nlohmann::json::object();
    for (int k = 0; k < base.numStandard(); ++k) values[base.standard_names[k]] = physical_theta[k];
    report["standard_estimate"] = {
        {"note", "physically consistent on every link (log-Cholesky parameters)"},
        {"values", values}};
    report["physically_consistent"] = physical_json;
  }
  if (vm.count("validate")) {
    const std::string file = vm["validate"].as<std::string>();
    const Observation test =
        observationFromTrajectory(model, readDatasetCsv(file, model.numJoints()));
    report["validation"] = validationJson(validateBaseEstimate(base, estimate.beta, test), file);
  }
  const std::string dir = vm["out"].as<std::string>();
  std::filesystem::create_directories(dir);
  writeFileAtomically(dir + "/estimate.json", report.dump(2) + "\n");
  writeFileAtomically(dir + "/estimate.md", estimateMarkdown(report));
  std::cout << model.name << ": " << (physical ? "pc" : leastSquaresMethodName(method))
            << " estimate of " << base.numBase() << " base parameters from " << train.num_samples
            << " samples, condition number " << formatShort(estimate.condition_number)
            << ", residual RMS "
            << formatShort(estimate.residual_rms.norm() / std::sqrt(model.numJoints())) << " N m";
  if (vm.count("validate"))
    std::cout << ", held-out RMS "
              << formatShort(report["validation"]["torque_rms"].get<std::vector<double>>().front());
  std::cout << "\nwrote " << dir << "/estimate.json and " << dir << "/estimate.md\n";
  return kExitOk;
}

}  // namespace dynid::cli
