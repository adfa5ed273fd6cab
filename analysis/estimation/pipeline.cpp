#include "analysis/estimation/pipeline.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The least-squares outcome of a physically consistent estimate: its base fields.
LeastSquaresOutcome leastSquaresOfPhysical(const BaseParameters& base, const PhysicalEstimate& pc) {
  LeastSquaresOutcome out;
  out.estimate = pc.ols;
  out.estimate.beta = pc.beta;
  out.estimate.covariance = pc.covariance;
  out.estimate.std_dev = pc.std_dev;
  out.estimate.residual_rms = pc.residual_rms;
  setRelativeErrors(out.estimate);
  for (int j = 0; j < base.numBase(); ++j)
    out.estimate.relative_std_dev_percent[j] = pc.beta[j] != 0.0
                                                   ? 100.0 * pc.std_dev[j] / std::abs(pc.beta[j])
                                                   : std::numeric_limits<double>::infinity();
  out.standard = pc.theta;
  out.pc = pc;
  return out;
}

}  // namespace

std::string combinedNote(const CombinedResult& r) {
  std::string out =
      r.termination + "; torque term from " + formatNumber(r.initial_torque, 4, "n/a") + " to " +
      formatNumber(r.final_torque, 4, "n/a") + ", GC error from " +
      formatNumber(r.initial_gc, 4, "n/a") + " to " + formatNumber(r.final_gc, 4, "n/a");
  if (!r.moved) out = "no step was taken: the estimate is pc's (" + out + ")";
  return out;
}

namespace {

std::string budgetText(const SearchBudget& budget) {
  return budget.max_seconds > 0.0 ? formatNumber(budget.max_seconds) + " s"
                                  : std::to_string(budget.max_evaluations) + " evaluations";
}

}  // namespace

LeastSquaresOutcome leastSquaresEstimate(Method method, const BaseParameters& base,
                                         const LeastSquaresSource& source,
                                         const Eigen::VectorXd& prior,
                                         const PhysicalOptions& pc_options) {
  if ((source.observation == nullptr) == (source.stream == nullptr))
    throw InputError("a least-squares source is an observation or a stream, exactly one");
  if (method == Method::kPc)
    return leastSquaresOfPhysical(
        base,
        source.stream != nullptr
            ? estimatePhysicallyConsistent(base, source.layout, *source.stream, prior, pc_options)
            : estimatePhysicallyConsistent(base, *source.observation, prior, pc_options));
  if (method != Method::kOls && method != Method::kWls)
    throw InputError(std::string("'") + methodName(method) + "' is not a least-squares method (" +
                     methodList(leastSquaresMethods()) + ")");
  const LeastSquaresMethod kind =
      method == Method::kOls ? LeastSquaresMethod::kOrdinary : LeastSquaresMethod::kWeighted;
  LeastSquaresOutcome out;
  out.estimate = source.stream != nullptr ? source.stream->estimate(kind)
                                          : estimateBaseParameters(base, *source.observation, kind);
  out.standard = base.standardFromBase(out.estimate.beta, prior);
  return out;
}

LeastSquaresOutcome combinedEstimate(const Model& model, const BaseParameters& base,
                                     const LeastSquaresSource& source,
                                     const LeastSquaresOutcome& pc, const GcProblem& gc,
                                     const CombinedOptions& options, CombinedResult* detail,
                                     const Eigen::VectorXd* start_theta) {
  if (!pc.pc || !pc.pc->problem || !pc.pc->usable)
    throw InputError("the combined estimator starts from a usable physically consistent estimate");
  const PhysicalEstimate& start = *pc.pc;
  const std::shared_ptr<const PhysicalProblem> problem = start.problem;
  TorqueTerm torque;
  torque.cost = [problem](const Eigen::VectorXd& theta) { return problem->cost(theta); };
  torque.derivatives = [problem](const Eigen::VectorXd& theta, Eigen::VectorXd* g,
                                 Eigen::MatrixXd* h) { problem->derivatives(theta, g, h); };
  torque.scale = 0.5 * (problem->A * start.theta - problem->b).squaredNorm() + start.unexplained;
  const CombinedResult result = refineCombined(model, gc, base.coordinates(), torque,
                                               start_theta ? *start_theta : start.theta, options);
  LeastSquaresOutcome out = pc;
  out.standard = result.theta;
  out.estimate.beta = base.project(result.theta);
  Eigen::VectorXd squares;
  if (source.stream != nullptr) {
    squares = source.stream->residualSquares(out.estimate.beta);
  } else {
    const Observation& o = *source.observation;
    const Eigen::VectorXd residual = o.W * result.theta - o.tau;
    squares = Eigen::VectorXd::Zero(o.num_joints);
    for (Eigen::Index k = 0; k < residual.size(); ++k)
      squares[k % o.num_joints] += residual[k] * residual[k];
  }
  const Eigen::VectorXd rows =
      out.estimate.fitted_rows.size() == squares.size()
          ? Eigen::VectorXd(out.estimate.fitted_rows)
          : Eigen::VectorXd::Constant(squares.size(),
                                      static_cast<double>(out.estimate.num_samples));
  out.estimate.residual_rms = squares.cwiseQuotient(rows.cwiseMax(1.0)).cwiseSqrt();
  setRelativeErrors(out.estimate);
  out.pc->theta = result.theta;
  out.pc->beta = out.estimate.beta;
  out.pc->residual_rms = out.estimate.residual_rms;
  if (detail != nullptr) *detail = result;
  return out;
}

SearchResult dispatchSearch(Method method, const SearchContext& context, const GaOptions& ga,
                            const NloOptions& nlo) {
  switch (method) {
    case Method::kNlo:
      return runNlo(context, nlo);
    case Method::kGa:
      return runGa(context, ga);
    case Method::kHybrid:
      return runHybrid(context, ga, nlo);
    default:
      throw InputError(std::string("'") + methodName(method) + "' is not a search (" +
                       methodList(searchMethods()) + ")");
  }
}

MethodRunner::MethodRunner(EstimationProblem problem)
    : problem_(std::move(problem)),
      pool_(problem_.threads >= 1 ? problem_.threads : 1),
      workspace_(pool_.numThreads()) {
  if (problem_.threads < 1) throw InputError("threads must be >= 1");
  if (problem_.prior.size() == 0) problem_.prior = problem_.model.standardParameters();
  if (problem_.prior.size() != problem_.model.parameterLayout().size())
    throw InputError("the prior has " + std::to_string(problem_.prior.size()) +
                     " parameters, the model " +
                     std::to_string(problem_.model.parameterLayout().size()));
}

Model MethodRunner::modelWith(const Eigen::VectorXd& theta) const {
  Model m = problem_.model;
  m.setStandardParameters(theta);
  return m;
}

void MethodRunner::applyCovariancePolicy(Method method, LeastSquaresOutcome& ls) {
  const LeastSquaresSource& source = problem_.least_squares;
  if (problem_.covariance == CovariancePolicy::kWhite ||
      (source.observation == nullptr && !source.replay && source.summary == nullptr))
    return;  // the white covariance: ls.covariance says so
  problem_.control.say("identify: " + std::string(methodName(method)) +
                       " covariance (robust over batches of samples)");
  const ScoreWeights weights = scoreWeights(ls.estimate, method == Method::kWls);
  PhysicalEstimate* pc = ls.pc ? &*ls.pc : nullptr;
  if (source.summary != nullptr)
    ls.covariance = applyHacCovariance(*source.summary, weights, ls.estimate, pc);
  else if (source.observation != nullptr)
    ls.covariance =
        applyHacCovariance(*problem_.base, *source.observation, weights, ls.estimate, pc);
  else
    ls.covariance = applyHacCovariance(problem_.model, *problem_.base, source.replay, &pool(),
                                       weights, ls.estimate, pc, source.rows);
}

const LeastSquaresOutcome& MethodRunner::leastSquares(Method method) {
  const auto found = least_squares_.find(method);
  if (found != least_squares_.end()) return found->second.first;
  problem_.control.say(method == Method::kPc ? "identify: pc (physically consistent)"
                                             : std::string("identify: ") + methodName(method));
  if (problem_.base == nullptr)
    throw InputError(std::string("'") + methodName(method) + "' needs base parameters");
  const auto started = Clock::now();
  LeastSquaresOutcome ls = leastSquaresEstimate(method, *problem_.base, problem_.least_squares,
                                                problem_.prior, problem_.physical);
  applyCovariancePolicy(method, ls);
  return least_squares_.emplace(method, std::make_pair(std::move(ls), since(started)))
      .first->second.first;
}

const Model& MethodRunner::searchStart() {
  if (!start_) {
    if (problem_.search_start == SearchStart::kPhysicallyConsistent)
      start_ = modelWith(leastSquares(Method::kPc).standard);
    else
      start_ = problem_.start.value_or(problem_.model);
  }
  return *start_;
}

const ParameterSpace& MethodRunner::space(Method method) { return *sharedSpace(method); }

std::shared_ptr<const ParameterSpace> MethodRunner::sharedSpace(Method method) {
  const Method searched = searchOf(method);
  if (!isSearch(searched))
    throw InputError(std::string("'") + methodName(method) + "' does not search");
  const bool plane = problem_.mass_plane == MassPlane::kOn ||
                     (problem_.mass_plane == MassPlane::kAuto && searched != Method::kGa);
  std::shared_ptr<const ParameterSpace>& slot = spaces_[plane ? 1 : 0];
  if (!slot) {
    const Model& start = searchStart();
    SpaceOptions options = problem_.space;
    options.total_mass_constraint = plane;
    options.total_mass = problem_.total_mass.value_or(totalMass(start));
    slot = std::make_shared<const ParameterSpace>(start, options);
  }
  return slot;
}

const SearchResult* MethodRunner::searchResult(Method method) const {
  const auto it = searches_.find(method);
  return it == searches_.end() ? nullptr : &it->second;
}

const SearchResult& MethodRunner::search(Method method) {
  const auto found = searches_.find(method);
  if (found != searches_.end()) return found->second;
  if (problem_.train_gc == nullptr)
    throw InputError(std::string("'") + methodName(method) + "' needs a GC-error problem");
  const ParameterSpace& space_of = space(method);
  problem_.control.say(std::string("search: ") + methodName(method) + " (" +
                       budgetText(problem_.search_budget) + ")");
  SearchContext context;
  context.space = &space_of;
  context.problem = problem_.train_gc;
  context.pool = &pool_;
  context.truth_full = problem_.truth_full;
  context.budget = problem_.search_budget;
  context.seed = problem_.seed;
  context.control = problem_.control;
  context.resume = problem_.resume;
  if (problem_.on_search_iteration)
    context.on_iteration = [&](const SearchState& state) {
      problem_.on_search_iteration(method, state, space_of);
    };
  SearchResult result = dispatchSearch(method, context, problem_.ga, problem_.nlo);
  return searches_.emplace(method, std::move(result)).first->second;
}

RefineResult MethodRunner::refineFrom(const ParameterSpace& space, const Eigen::VectorXd& x0,
                                      bool uncertainty) {
  if (problem_.train_gc == nullptr) throw InputError("a refinement needs a GC-error problem");
  RefineOptions options = problem_.refine.options;
  options.uncertainty = uncertainty;
  options.num_threads = pool_.numThreads();
  options.control = problem_.control;
  std::optional<BaseCoordinates> coordinates;
  if (problem_.base != nullptr) coordinates = problem_.base->coordinates();
  return refineGc(space, *problem_.train_gc, x0, options, coordinates ? &*coordinates : nullptr);
}

Estimate MethodRunner::refine(Method method) {
  const Method searched = searchOf(method);
  const SearchResult& found = search(searched);
  const ParameterSpace& space_of = space(searched);
  const RefineSettings& settings = problem_.refine;
  problem_.control.say(std::string("refine: ") + methodName(searched) + " (at most " +
                       std::to_string(settings.options.max_iterations) + " iterations" +
                       (settings.options.max_seconds > 0.0
                            ? ", " + std::to_string(settings.options.max_seconds) + " s"
                            : std::string()) +
                       ")");
  const RefineResult refined = refineFrom(space_of, found.best_x, false);
  Estimate out;
  out.method = method;
  out.model = space_of.modelAt(refined.x);
  out.evaluations = refined.base_iterations + refined.iterations;
  out.seconds = refined.seconds;
  out.start_gc = refined.initial_gc;
  out.note = refined.termination + "; GC error from " + std::to_string(refined.initial_gc) +
             " to " + std::to_string(refined.final_gc);
  const Model searched_model = space_of.modelAt(found.best_x);
  if (settings.keep_if_better) {
    // The refinement's start is the search's point projected onto the space (bounds, mass
    // plane); a refinement that ends above the search's own training GC error is not kept.
    if (!(gcError(out.model, *problem_.train_gc, workspace_, pool_) <=
          gcError(searched_model, *problem_.train_gc, workspace_, pool_))) {
      out.model = searched_model;
      out.note = "kept the search's result: the refinement did not lower its training GC error (" +
                 out.note + ")";
    }
  }
  out.moved = out.model.standardParameters() != searched_model.standardParameters();
  if (!out.moved && out.note.rfind("kept the search's result", 0) != 0)
    out.note = "the refinement ended at the search's result (" + out.note + ")";
  return out;
}

Estimate MethodRunner::combined() {
  if (!combined_) {
    if (problem_.train_gc == nullptr) throw InputError("'combined' needs a GC-error problem");
    const LeastSquaresOutcome& pc = leastSquares(Method::kPc);
    problem_.control.say("identify: combined (torques and motion, physically consistent)");
    CombinedOptions options = problem_.combined;
    options.num_threads = pool_.numThreads();
    options.control = problem_.control;
    CombinedResult detail;
    LeastSquaresOutcome ls =
        combinedEstimate(problem_.model, *problem_.base, problem_.least_squares, pc,
                         *problem_.train_gc, options, &detail);
    combined_.emplace(std::move(ls), detail.seconds);
    combined_detail_ = std::move(detail);
  }
  Estimate out;
  out.method = Method::kCombined;
  out.model = modelWith(combined_->first.standard);
  out.evaluations = combined_detail_->iterations;
  out.seconds = combined_->second;
  out.note = combinedNote(*combined_detail_);
  out.moved = combined_detail_->moved;
  out.least_squares = &combined_->first;
  return out;
}

Estimate MethodRunner::run(Method method) {
  if (method == Method::kCombined) return combined();
  if (!isSearch(method) && !isRefined(method)) {
    const LeastSquaresOutcome& ls = leastSquares(method);
    Estimate out;
    out.method = method;
    out.model = modelWith(ls.standard);
    out.evaluations = ls.pc ? ls.pc->iterations : 0;
    out.seconds = least_squares_.at(method).second;
    out.least_squares = &ls;
    return out;
  }
  if (isRefined(method)) return refine(method);
  const SearchResult& found = search(method);
  Estimate out;
  out.method = method;
  out.model = space(method).modelAt(found.best_x);
  out.evaluations = found.evaluations;
  out.seconds = found.seconds;
  return out;
}

}  // namespace dynid
