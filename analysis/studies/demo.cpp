#include "analysis/studies/demo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "analysis/runs/arm.hpp"
#include "analysis/studies/correlation.hpp"
#include "analysis/studies/study.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"

namespace dynid {

void DemoOptions::check() const {
  checkOption("demo", "threads", threads, "`threads`");
  checkOption("demo", "search-seconds", search_seconds, "`search_seconds`");
  checkOption("demo", "search-evaluations", static_cast<double>(search_evaluations),
              "`search_evaluations`");
  checkOption("demo", "refine-iterations", refine_iterations, "`refine_iterations`");
  checkOption("demo", "refine-seconds", refine_seconds, "`refine_seconds`");
  checkOption("demo", "prior-weight", prior_weight, "`prior_weight`");
}

DemoResult runDemo(const DemoOptions& options) {
  options.check();
  const auto start = std::chrono::steady_clock::now();
  const auto stopped = [&] { return options.control.interrupted(); };
  StudySettings study_settings;
  study_settings.train_seconds = study_settings.test_seconds = options.quick ? 4.0 : 10.0;
  study_settings.segments = options.quick ? 20 : 100;
  study_settings.search_evaluations = options.search_evaluations;
  study_settings.search_seconds = options.search_seconds > 0       ? options.search_seconds
                                  : options.search_evaluations > 0 ? 0.0
                                                                   : (options.quick ? 2.0 : 30.0);
  study_settings.refine_iterations = options.refine_iterations > 0 ? options.refine_iterations
                                     : options.quick               ? 30
                                                                   : 200;
  study_settings.refine_seconds = options.refine_seconds;
  study_settings.prior_weight = options.prior_weight;
  study_settings.keep_if_better = options.keep_if_better;
  study_settings.seed = options.seed;
  study_settings.threads = resolveThreads(options.threads);
  Study study(study_settings, options.control);

  DemoResult result;
  result.settings = study_settings;
  result.quick = options.quick;

  const BaseParameters& base = study.base();
  DemoIdentifiability& ident = result.identifiability;
  ident.num_standard = base.numStandard();
  ident.num_base = base.numBase();
  for (int j = 0; j < base.numBase(); ++j) {
    ident.base_names.push_back(base.baseName(j));
    ident.base_expressions.push_back(base.expression(j));
  }
  for (int k : base.zero_columns) ident.unidentifiable.push_back(base.standard_names[k]);
  ident.condition_number = scaledConditionNumber(base.baseRegressor(study.observation().W));

  // Least squares always; the rest stage by stage until interrupted.
  std::vector<Method> methods;
  for (Method method : allMethods())
    if (method != Method::kCombined) methods.push_back(method);  // combined: dynid study
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const Method method = methods[k];
    if (method != Method::kOls && method != Method::kWls && stopped()) break;
    options.control.say(
        std::string(methodName(method)) + ", method " + std::to_string(k + 1) + " of " +
        std::to_string(methods.size()) + "; " +
        progressText(
            static_cast<double>(k) / static_cast<double>(methods.size()),
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()) +
        " (of the methods)");
    result.methods.push_back(study.run(method));
  }
  for (Method method : searchMethods()) {
    const SearchResult* found = study.searchResult(method);
    if (found == nullptr) continue;
    DemoSearchTrace trace;
    trace.method = methodName(method);
    trace.history = found->history;
    if (const std::vector<double>* e = study.searchBaseErrors(method)) trace.base_errors = *e;
    trace.candidates = static_cast<long>(found->evaluated.size());
    const std::size_t every = found->evaluated.size() / 2000 + 1;
    for (std::size_t i = 0; i < found->evaluated.size(); i += every)
      trace.evaluated.push_back(found->evaluated[i]);
    std::vector<double> gc, error;
    for (const auto& [g, e] : found->evaluated)
      if (g > 0.0 && e > 0.0 && std::isfinite(g) && std::isfinite(e))
        gc.push_back(std::log10(g)), error.push_back(std::log10(e));
    trace.pearson_log = pearson(gc, error);
    trace.spearman = spearman(gc, error);
    result.searches.push_back(std::move(trace));
  }
  if (!result.methods.empty()) result.initial_gc_train = result.methods.front().gc_error_initial;
  const Eigen::VectorXd& sigma = study.olsRelativeStdDev();
  ident.ols_relative_std_dev.assign(sigma.data(), sigma.data() + sigma.size());
  if (!stopped()) result.null_spaces = study.nullSpaces();
  result.initial_gc_test = study.initialTestGc();
  for (const MethodMetrics& m : result.methods)
    if (m.key == methodName(Method::kNlo) && !stopped())
      result.near_truth = study.nearTruth(options.quick ? 40 : 200, 0.02, methodName(Method::kNlo),
                                          m.gc_error_test);
  result.interrupted = stopped();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace dynid
