#include "search/refine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include <ceres/ceres.h>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/errors.hpp"
#include "core/integrators-inl.hpp"
#include "core/model-inl.hpp"

namespace dynid {

namespace {

// Jet width of the automatic differentiation passes: DynamicAutoDiffCostFunction differentiates
// this many parameters per rollout.
constexpr int kStride = 8;

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Model parameters from the search's free parameters x.
struct FreeMap {
  const ParameterSpace* space;
  template <typename T>
  void apply(const T* x, ModelTpl<T>& model) const {
    space->linkInertiasAt(x, model.inertias);
    model.updateFrameInertias();
  }
};

/// Model parameters from the standard parameters theta directly.
struct StandardMap {
  template <typename T>
  void apply(const T* theta, ModelTpl<T>& model) const {
    const int p = model.parameterLayout().size();
    model.setStandardParameters(Eigen::Map<const VectorX<T>>(theta, p));
  }
};

/// Model parameters from base parameters beta: theta = theta_ref + L (beta - beta_ref), L a right
/// inverse of P.
struct BetaMap {
  Eigen::VectorXd theta_ref, beta_ref;
  Eigen::MatrixXd lift;  // p x b
  template <typename T>
  void apply(const T* beta, ModelTpl<T>& model) const {
    VectorX<T> theta = theta_ref.cast<T>();
    for (int j = 0; j < beta_ref.size(); ++j) {
      const T delta = beta[j] - beta_ref[j];
      for (int k = 0; k < theta.size(); ++k)
        if (lift(k, j) != 0.0) theta[k] += lift(k, j) * delta;
    }
    model.setStandardParameters(theta);
  }
};

/// Residuals of one segment (see refine.hpp) for any Scalar. Parameter blocks: the model's, then
/// the segment's start when `with_start`, then the next segment's start when `continuity` > 0
/// (its end residual then measures the gap to that start instead of to the measured end state).
template <typename Map>
struct SegmentFunctor {
  Model structure;
  Map map;
  const GcProblem* problem;
  int segment;
  bool with_start;
  double continuity;

  template <typename T>
  bool operator()(T const* const* blocks, T* residuals) const {
    using std::isfinite;
    const int n = structure.numJoints();
    ModelTpl<T> model = structure.template cast<T>();
    map.apply(blocks[0], model);
    DataTpl<T> data(model);
    const Trajectory& recorded = problem->data;
    const int start = problem->starts[segment];
    const int end = start + problem->samples_per_segment;
    // Start state: estimated or measured.
    VectorX<T> q(n), dq(n), tau(n);
    for (int j = 0; j < n; ++j) {
      q[j] = with_start ? blocks[1][j] : T(recorded.q(j, start));
      dq[j] = with_start ? blocks[1][n + j] : T(recorded.dq(j, start));
    }
    // Roll out with the recorded (held) torques.
    const T h(problem->step);
    for (int k = start; k < end; ++k) {
      for (int j = 0; j < n; ++j) tau[j] = T(recorded.tau(j, k));
      for (int sub = 0; sub < problem->substeps; ++sub)
        integratorStep(problem->integrator, model, data, q, dq, tau, h);
    }
    int r = 0;
    if (with_start) {
      for (int j = 0; j < n; ++j)
        residuals[r++] = problem->weight_q[j] * (blocks[1][j] - recorded.q(j, start));
      for (int j = 0; j < n; ++j)
        residuals[r++] = problem->weight_dq[j] * (blocks[1][n + j] - recorded.dq(j, start));
    }
    if (continuity > 0.0) {
      for (int j = 0; j < n; ++j)
        residuals[r++] = continuity * problem->weight_q[j] * (q[j] - blocks[2][j]);
      for (int j = 0; j < n; ++j)
        residuals[r++] = continuity * problem->weight_dq[j] * (dq[j] - blocks[2][n + j]);
    } else {
      for (int j = 0; j < n; ++j)
        residuals[r++] = problem->weight_q[j] * (q[j] - recorded.q(j, end));
      for (int j = 0; j < n; ++j)
        residuals[r++] = problem->weight_dq[j] * (dq[j] - recorded.dq(j, end));
    }
    // A diverged rollout is an evaluation failure: Ceres rejects the step.
    for (int i = 0; i < r; ++i)
      if (!isfinite(residuals[i])) return false;
    return true;
  }
};

/// `continuity` > 0 only with `with_start`: the segment then ends on the next one's start.
template <typename Map>
std::unique_ptr<ceres::CostFunction> segmentCost(const Model& structure, const Map& map,
                                                 int map_size, const GcProblem& problem,
                                                 int segment, bool with_start,
                                                 double continuity = 0.0) {
  const int n = structure.numJoints();
  if (!with_start) continuity = 0.0;
  auto cost = std::make_unique<ceres::DynamicAutoDiffCostFunction<SegmentFunctor<Map>, kStride>>(
      new SegmentFunctor<Map>{structure, map, &problem, segment, with_start, continuity});
  cost->AddParameterBlock(map_size);
  if (with_start) cost->AddParameterBlock(2 * n);
  if (continuity > 0.0) cost->AddParameterBlock(2 * n);
  cost->SetNumResiduals((with_start ? 4 : 2) * n);
  return cost;
}

/// The segment that starts where segment s ends, or -1 (see RefineOptions::continuity_weight).
int nextSegment(const GcProblem& problem, int s) {
  if (s + 1 >= problem.numSegments()) return -1;
  return problem.starts[s + 1] == problem.starts[s] + problem.samples_per_segment ? s + 1 : -1;
}

/// The continuity weight of segment s's end residual: > 0 when it ends on the next start.
double continuityOf(const GcProblem& problem, const RefineOptions& options, int s) {
  if (!options.estimate_initial_states || options.continuity_weight <= 0.0) return 0.0;
  return nextSegment(problem, s) >= 0 ? options.continuity_weight : 0.0;
}

/// Whether any segment ends on the next one's start (the starts are then not independent).
bool anyChained(const GcProblem& problem, const RefineOptions& options) {
  for (int s = 0; s < problem.numSegments(); ++s)
    if (continuityOf(problem, options, s) > 0.0) return true;
  return false;
}

/// The parameter blocks of segment s's residuals: `model_block`, then its start and the next
/// segment's start as needed.
std::vector<double*> segmentBlocks(const GcProblem& problem, const RefineOptions& options, int s,
                                   double* model_block, Eigen::MatrixXd& starts) {
  std::vector<double*> blocks{model_block};
  if (options.estimate_initial_states) blocks.push_back(starts.col(s).data());
  if (continuityOf(problem, options, s) > 0.0) blocks.push_back(starts.col(s + 1).data());
  return blocks;
}

/// theta(x) as residuals, to differentiate the parameter map.
struct StandardOfFree {
  Model structure;
  FreeMap map;
  template <typename T>
  bool operator()(T const* const* blocks, T* residuals) const {
    ModelTpl<T> model = structure.template cast<T>();
    map.apply(blocks[0], model);
    const VectorX<T> theta = model.standardParameters();
    for (int k = 0; k < theta.size(); ++k) residuals[k] = theta[k];
    return true;
  }
};

/// W (P theta(x) - beta_target), W = diag(1 / |beta_target|): the map back from beta to x.
struct BetaOfFree {
  Model structure;
  FreeMap map;
  Eigen::MatrixXd weighted_projection;  // W P
  Eigen::VectorXd weighted_target;      // W beta_target
  template <typename T>
  bool operator()(T const* const* blocks, T* residuals) const {
    ModelTpl<T> model = structure.template cast<T>();
    map.apply(blocks[0], model);
    const VectorX<T> theta = model.standardParameters();
    for (int i = 0; i < weighted_projection.rows(); ++i) {
      T sum = T(-weighted_target[i]);
      for (int k = 0; k < theta.size(); ++k)
        if (weighted_projection(i, k) != 0.0) sum += weighted_projection(i, k) * theta[k];
      residuals[i] = sum;
    }
    return true;
  }
};

/// Linear residuals r = A x - b on the free parameters (the total mass and the gauge).
class LinearResidual : public ceres::CostFunction {
 public:
  LinearResidual(Eigen::MatrixXd a, Eigen::VectorXd b) : a_(std::move(a)), b_(std::move(b)) {
    set_num_residuals(static_cast<int>(a_.rows()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(a_.cols()));
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Map<const Eigen::VectorXd> x(parameters[0], a_.cols());
    Eigen::Map<Eigen::VectorXd>(residuals, a_.rows()) = a_ * x - b_;
    if (jacobians != nullptr && jacobians[0] != nullptr)
      Eigen::Map<RowMajor>(jacobians[0], a_.rows(), a_.cols()) = a_;
    return true;
  }

 private:
  Eigen::MatrixXd a_;
  Eigen::VectorXd b_;
};

class RefineCallback : public ceres::IterationCallback {
 public:
  RefineCallback(std::vector<RefineIteration>& history, const std::atomic<bool>* stop,
                 bool& interrupted, std::string stage, double time_offset)
      : history_(history),
        stop_(stop),
        interrupted_(interrupted),
        stage_(std::move(stage)),
        time_offset_(time_offset) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    history_.push_back({stage_, summary.iteration, summary.cost, summary.gradient_max_norm,
                        time_offset_ + summary.cumulative_time_in_seconds});
    if (stop_ != nullptr && stop_->load()) {
      interrupted_ = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  std::vector<RefineIteration>& history_;
  const std::atomic<bool>* stop_;
  bool& interrupted_;
  std::string stage_;
  double time_offset_;
};

/// Typical magnitude for scaling: |v_j|, or the mean magnitude of the non-zero entries for a 0
/// (an entry below 1e-9 of the mean magnitude counts as a round-off 0).
Eigen::VectorXd magnitudes(const Eigen::VectorXd& v) {
  const double mean = v.size() > 0 ? v.cwiseAbs().mean() : 0.0;
  const auto zero = [&](double e) { return std::abs(e) <= 1e-9 * mean; };
  double sum = 0.0;
  int count = 0;
  for (double e : v)
    if (!zero(e)) sum += std::abs(e), ++count;
  const double fallback = count > 0 ? sum / count : 1.0;
  Eigen::VectorXd out(v.size());
  for (int j = 0; j < v.size(); ++j) out[j] = zero(v[j]) ? fallback : std::abs(v[j]);
  return out;
}

/// d beta / d x = P d theta / d x at x, with beta scaled by its magnitudes and x by its own (or
/// half its range for a zero): singular values, numerical rank and right singular vectors.
struct FreeAnalysis {
  Eigen::VectorXd singular_values, x_scale;
  Eigen::MatrixXd v;  // k x k; columns rank.. span the free directions (in scaled x)
  int rank = 0;
};

FreeAnalysis analyseFreeDirections(const Model& structure, const ParameterSpace& space,
                                   const Eigen::MatrixXd& P, const Eigen::VectorXd& x) {
  const int k = space.numFree();
  const int p = static_cast<int>(P.cols());
  auto map_cost = std::make_unique<ceres::DynamicAutoDiffCostFunction<StandardOfFree, kStride>>(
      new StandardOfFree{structure, FreeMap{&space}});
  map_cost->AddParameterBlock(k);
  map_cost->SetNumResiduals(p);
  RowMajor jtheta(p, k);
  Eigen::VectorXd theta(p);
  const double* x_pointer[1] = {x.data()};
  double* jacobian[1] = {jtheta.data()};
  map_cost->Evaluate(x_pointer, theta.data(), jacobian);
  FreeAnalysis out;
  out.x_scale = magnitudes(x);
  for (int j = 0; j < k; ++j)
    if (x[j] == 0.0) out.x_scale[j] = 0.5 * (space.upper()[j] - space.lower()[j]);
  const Eigen::MatrixXd scaled =
      magnitudes(P * theta).cwiseInverse().asDiagonal() * P * jtheta * out.x_scale.asDiagonal();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeFullV);
  out.singular_values = svd.singularValues();
  out.v = svd.matrixV();
  const double top = out.singular_values.size() > 0 ? out.singular_values[0] : 0.0;
  for (double s : out.singular_values)
    if (s > 1e-9 * top) ++out.rank;
  return out;
}

/// w (fixed mass + sum of free masses - total), w = 1 / (tolerance total): the total mass held to
/// about `tolerance` relative.
std::unique_ptr<ceres::CostFunction> totalMassCost(const ParameterSpace& space, double tolerance) {
  const double total = space.options().total_mass;
  const double w = 1.0 / (tolerance * std::max(std::abs(total), 1e-12));
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(1, space.numFree());
  for (int p : space.massPositions()) a(0, p) = w;
  return std::make_unique<LinearResidual>(
      a, Eigen::VectorXd::Constant(1, w * (total - space.fixedMass())));
}

/// J^T J of the GC residuals with respect to beta at `beta` (`map` lifts beta to the model), the
/// starts eliminated by their Schur complement when estimated (a sparse LDL^T of the starts' block
/// tridiagonal J^T J, block diagonal when no segment ends on the next start); `squared` gets the
/// sum of squared residuals (NaN when a rollout diverged).
Eigen::MatrixXd betaInformation(const Model& structure, const BetaMap& map,
                                const GcProblem& problem, const Eigen::VectorXd& beta,
                                Eigen::MatrixXd starts, const RefineOptions& options,
                                ThreadPool& pool, double& squared_sum) {
  const int b = static_cast<int>(beta.size()), n = structure.numJoints();
  const int segments = problem.numSegments();
  const bool with_start = options.estimate_initial_states;
  const int m = (with_start ? 4 : 2) * n;
  std::vector<RowMajor> jb(segments), js(segments), jn(segments);
  Eigen::VectorXd squared(segments);
  pool.parallelFor(segments, [&](int s, int) {
    const double continuity = continuityOf(problem, options, s);
    const auto cost = segmentCost(structure, map, b, problem, s, with_start, continuity);
    Eigen::VectorXd probe = beta;
    const std::vector<double*> blocks = segmentBlocks(problem, options, s, probe.data(), starts);
    const std::vector<const double*> parameters(blocks.begin(), blocks.end());
    jb[s].resize(m, b);
    js[s].resize(m, with_start ? 2 * n : 0);
    jn[s].resize(m, continuity > 0.0 ? 2 * n : 0);
    double* jacobians[3] = {jb[s].data(), js[s].data(), jn[s].data()};
    Eigen::VectorXd r(m);
    if (!cost->Evaluate(parameters.data(), r.data(), jacobians)) {
      jb[s].setZero(), js[s].setZero(), jn[s].setZero();
      squared[s] = std::numeric_limits<double>::quiet_NaN();
      return;
    }
    squared[s] = r.squaredNorm();
  });
  squared_sum = squared.sum();
  return eliminateStarts(jb, js, jn);
}

/// Base-coordinate uncertainty and the free directions of x (see refine.hpp).
void baseUncertainty(const Model& structure, const ParameterSpace& space, const GcProblem& problem,
                     const BaseCoordinates& base, const RefineOptions& options,
                     RefineResult& result, ThreadPool& pool) {
  const bool with_start = options.estimate_initial_states;
  const Eigen::VectorXd theta = space.standardAt(result.x);
  const Eigen::MatrixXd& P = base.projection;  // its size checked by refineGc
  const int b = static_cast<int>(P.rows()), n = structure.numJoints();
  const int segments = problem.numSegments();
  result.beta = P * theta;
  const Eigen::MatrixXd lift = P.completeOrthogonalDecomposition().pseudoInverse();
  const BetaMap map{theta, result.beta, lift};
  double squared = 0.0;
  const Eigen::MatrixXd H = betaInformation(structure, map, problem, result.beta,
                                            result.initial_states, options, pool, squared);
  const int m = (with_start ? 4 : 2) * n;
  const long rows = static_cast<long>(segments) * m;
  const long unknowns = b + (with_start ? 2L * n * segments : 0L);
  result.degrees_of_freedom = static_cast<int>(std::max(rows - unknowns, 1L));
  result.sigma2 = squared / result.degrees_of_freedom;
  // cov = sigma^2 H^-1, through the symmetric eigendecomposition of the Jacobi-scaled H.
  Eigen::VectorXd d(b);
  for (int j = 0; j < b; ++j) d[j] = H(j, j) > 0.0 ? 1.0 / std::sqrt(H(j, j)) : 1.0;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(d.asDiagonal() * H * d.asDiagonal());
  const Eigen::VectorXd values = eigen.eigenvalues();
  const double largest = values.cwiseAbs().maxCoeff();
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(b);
  result.information_rank = 0;
  for (int j = 0; j < b; ++j)
    if (values[j] > 1e-12 * largest) inverse[j] = 1.0 / values[j], ++result.information_rank;
  result.beta_covariance = result.sigma2 * d.asDiagonal() * eigen.eigenvectors() *
                           inverse.asDiagonal() * eigen.eigenvectors().transpose() * d.asDiagonal();
  result.beta_std_dev = result.beta_covariance.diagonal().cwiseMax(0.0).cwiseSqrt();

  // The directions of x that leave beta unchanged, at the estimate.
  if (space.numFree() == 0) return;
  const FreeAnalysis analysis = analyseFreeDirections(structure, space, P, result.x);
  result.beta_singular = analysis.singular_values;
  result.free_parameter_rank = analysis.rank;
  const std::vector<std::string> names = space.freeNames();
  for (int c = analysis.rank; c < space.numFree(); ++c) {
    const Eigen::VectorXd v = analysis.x_scale.asDiagonal() * analysis.v.col(c);
    const double lead = v.cwiseAbs().maxCoeff();
    std::vector<std::pair<std::string, double>> combination;
    for (int j = 0; j < space.numFree(); ++j)
      if (std::abs(v[j]) >= 1e-3 * lead) combination.emplace_back(names[j], v[j] / lead);
    std::sort(combination.begin(), combination.end(), [](const auto& a, const auto& b2) {
      return std::abs(a.second) > std::abs(b2.second);
    });
    // Sign: the leading coefficient positive.
    if (!combination.empty() && combination.front().second < 0)
      for (auto& entry : combination) entry.second = -entry.second;
    result.free_directions.push_back({combination});
  }
}

}  // namespace

Eigen::MatrixXd eliminateStarts(const std::vector<RowMajor>& jb, const std::vector<RowMajor>& js,
                                const std::vector<RowMajor>& jn) {
  const int segments = static_cast<int>(jb.size());
  if (segments == 0) return {};
  const Eigen::Index b = jb[0].cols();
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(b, b);
  for (const RowMajor& j : jb) H.noalias() += j.transpose() * j;
  const Eigen::Index w = js[0].cols();
  if (w == 0) return H;
  // H - B^T A^-1 B with A = Js^T Js (block tridiagonal when chained) and B = Js^T Jb over the
  // stacked starts.
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(w * segments, b);
  const auto add = [&](int row_block, int col_block, const Eigen::MatrixXd& block) {
    for (Eigen::Index i = 0; i < w; ++i)
      for (Eigen::Index j = 0; j < w; ++j)
        entries.emplace_back(row_block * w + i, col_block * w + j, block(i, j));
  };
  for (int s = 0; s < segments; ++s) {
    add(s, s, js[s].transpose() * js[s]);
    B.middleRows(s * w, w).noalias() += js[s].transpose() * jb[s];
    if (jn[s].cols() == 0) continue;
    const Eigen::MatrixXd cross = js[s].transpose() * jn[s];
    add(s, s + 1, cross);
    add(s + 1, s, cross.transpose());
    add(s + 1, s + 1, jn[s].transpose() * jn[s]);
    B.middleRows((s + 1) * w, w).noalias() += jn[s].transpose() * jb[s];
  }
  Eigen::SparseMatrix<double> A(w * segments, w * segments);
  A.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
  if (ldlt.info() != Eigen::Success) return Eigen::MatrixXd::Constant(b, b, std::nan(""));
  H.noalias() -= B.transpose() * ldlt.solve(B);
  return H;
}

std::unique_ptr<ceres::CostFunction> makeSegmentCost(const Model& structure,
                                                     const ParameterSpace& space,
                                                     const GcProblem& problem, int segment,
                                                     bool with_start, double continuity) {
  return segmentCost(structure, FreeMap{&space}, space.numFree(), problem, segment, with_start,
                     continuity);
}

Eigen::MatrixXd gcJacobian(const Model& model, const GcProblem& problem, int num_threads) {
  const int n = model.numJoints(), p = model.parameterLayout().size();
  if (problem.data.numJoints() != n)
    throw InputError("the data has " + std::to_string(problem.data.numJoints()) +
                     " joints, the model " + std::to_string(n));
  const int segments = problem.numSegments();
  Eigen::MatrixXd J(2 * n * segments, p);
  const Eigen::VectorXd theta = model.standardParameters();
  std::vector<char> ok(segments, 1);
  ThreadPool pool(std::max(num_threads, 1));
  pool.parallelFor(segments, [&](int s, int) {
    const auto cost = segmentCost(model, StandardMap{}, p, problem, s, false);
    RowMajor js(2 * n, p);
    Eigen::VectorXd r(2 * n);
    const double* parameters[1] = {theta.data()};
    double* jacobians[1] = {js.data()};
    ok[s] = cost->Evaluate(parameters, r.data(), jacobians) ? 1 : 0;
    J.middleRows(2 * n * s, 2 * n) = js;
  });
  for (int s = 0; s < segments; ++s)
    if (!ok[s]) throw NumericalError("the rollout of segment " + std::to_string(s) + " diverged");
  return J;
}

std::unique_ptr<ceres::CostFunction> makeTotalMassCost(const ParameterSpace& space) {
  return totalMassCost(space, 1e-6);
}

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Solver settings shared by the stages: Levenberg-Marquardt. Independent starts (when
/// estimated) are eliminated first by a block-sparse Schur complement; chained ones (a segment
/// ending on the next start, so no longer an independent set) go with the model parameters into a
/// sparse Cholesky factorisation of the normal equations, whose starts' part is block tridiagonal.
ceres::Solver::Options solverOptions(const RefineOptions& options, const GcProblem& problem,
                                     double* model_block, Eigen::MatrixXd& starts,
                                     double seconds_left) {
  ceres::Solver::Options solver;
  solver.minimizer_type = ceres::TRUST_REGION;
  solver.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  const bool sparse = ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE);
  if (options.estimate_initial_states && anyChained(problem, options)) {
    solver.linear_solver_type = sparse ? ceres::SPARSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
  } else if (options.estimate_initial_states) {
    solver.linear_solver_type = sparse ? ceres::SPARSE_SCHUR : ceres::DENSE_SCHUR;
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    for (int s = 0; s < starts.cols(); ++s) ordering->AddElementToGroup(starts.col(s).data(), 0);
    ordering->AddElementToGroup(model_block, 1);
    solver.linear_solver_ordering = ordering;
  } else {
    solver.linear_solver_type = ceres::DENSE_QR;
  }
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  solver.gradient_tolerance = options.gradient_tolerance;
  solver.parameter_tolerance = options.parameter_tolerance;
  if (options.max_seconds > 0.0) solver.max_solver_time_in_seconds = std::max(seconds_left, 1e-3);
  solver.num_threads = std::max(options.num_threads, 1);
  solver.logging_type = ceres::SILENT;
  return solver;
}

std::string terminationOf(const ceres::Solver::Summary& summary) {
  return std::string(ceres::TerminationTypeToString(summary.termination_type)) + ": " +
         summary.message;
}

/// The base stage: the GC residuals as a function of beta, solved by Levenberg-Marquardt from
/// beta(x); then x is fitted to the solution's beta within the bounds (and on the total-mass
/// plane). Updates result.x (when the map back predicts no worse than the start), the starts and
/// the base-stage fields.
void baseStage(const Model& structure, const ParameterSpace& space, const GcProblem& problem,
               const BaseCoordinates& base, const RefineOptions& options,
               std::chrono::steady_clock::time_point clock_start, GcWorkspace& workspace,
               ThreadPool& pool, RefineResult& result) {
  const bool with_start = options.estimate_initial_states;
  const Eigen::MatrixXd& P = base.projection;
  const Eigen::VectorXd theta0 = space.standardAt(result.x);
  const int b = static_cast<int>(P.rows());
  Eigen::VectorXd beta = P * theta0;
  const BetaMap map{theta0, beta, P.completeOrthogonalDecomposition().pseudoInverse()};

  ceres::Problem beta_problem;
  for (int s = 0; s < problem.numSegments(); ++s) {
    beta_problem.AddResidualBlock(
        segmentCost(structure, map, b, problem, s, with_start, continuityOf(problem, options, s))
            .release(),
        nullptr, segmentBlocks(problem, options, s, beta.data(), result.initial_states));
  }
  ceres::Solver::Options solver =
      solverOptions(options, problem, beta.data(), result.initial_states,
                    options.max_seconds - secondsSince(clock_start));
  RefineCallback callback(result.history, options.stop, result.interrupted, "base",
                          secondsSince(clock_start));
  solver.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &beta_problem, &summary);
  result.base_stage = true;
  result.base_beta = beta;
  result.base_termination = terminationOf(summary);
  result.base_iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.initial_cost = summary.initial_cost;
  {
    Model at_beta = structure;
    at_beta.setStandardParameters(theta0 + map.lift * (beta - map.beta_ref));
    result.base_gc = gcError(at_beta, problem, workspace, pool);
  }

  // Map back: min |R (P theta(x) - beta)|^2 over x within the bounds, with R^T R = H the GC
  // residuals' J^T J in beta at the solution: the Gauss-Newton model of the GC error's increase,
  // so that a beta the free parameters cannot reproduce exactly (noisy data) is approached where
  // the data determine it best. R is normalised to a unit misfit at the estimate. Should a rollout
  // diverge there, relative weights 1 / |beta| replace it.
  const Eigen::VectorXd weights = magnitudes(beta).cwiseInverse();
  Eigen::MatrixXd weighting = weights.asDiagonal();
  {
    double squared = 0.0;
    const Eigen::MatrixXd H = betaInformation(structure, map, problem, beta, result.initial_states,
                                              options, pool, squared);
    if (H.allFinite()) {
      Eigen::VectorXd d(b);
      for (int j = 0; j < b; ++j) d[j] = H(j, j) > 0.0 ? 1.0 / std::sqrt(H(j, j)) : 1.0;
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(d.asDiagonal() * H *
                                                                 d.asDiagonal());
      const Eigen::VectorXd root = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();
      const Eigen::MatrixXd r =
          root.asDiagonal() * eigen.eigenvectors().transpose() * d.cwiseInverse().asDiagonal();
      const double misfit = (r * (P * theta0 - beta)).norm();
      if (misfit > 0.0 && std::isfinite(misfit)) weighting = r / misfit;
    }
  }
  const Eigen::MatrixXd weighted_projection = weighting * P;
  const Eigen::VectorXd weighted_target = weighting * beta;
  const int k = space.numFree();
  const int tries = 2 + std::max(options.map_back_starts, 0);
  std::vector<Eigen::VectorXd> fitted(tries);
  Eigen::VectorXd fit_cost(tries);
  std::mt19937_64 random(20260101);  // fixed: refinement is deterministic
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Eigen::VectorXd centre = 0.5 * (space.lower() + space.upper());
  const Eigen::VectorXd half_range = (0.5 * (space.upper() - space.lower())).cwiseMax(1e-300);
  for (int t = 0; t < tries; ++t) {
    fitted[t] = t == 0 ? result.x : centre;
    if (t > 1)
      for (int j = 0; j < k; ++j)
        fitted[t][j] = space.lower()[j] + uniform(random) * (space.upper()[j] - space.lower()[j]);
    fitted[t] = space.project(fitted[t]);
  }
  pool.parallelFor(tries, [&](int t, int) {
    Eigen::VectorXd& x = fitted[t];
    // The map is curved (products m c, m c c^T) and LM from a point alone stops at a bound: each
    // fit is a continuation, with a pull eps |(x - centre) / half range|^2 towards the box's
    // centre taken down from 1e-1 to 0.
    for (const double eps : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 0.0}) {
      auto fit = std::make_unique<ceres::DynamicAutoDiffCostFunction<BetaOfFree, kStride>>(
          new BetaOfFree{structure, FreeMap{&space}, weighted_projection, weighted_target});
      fit->AddParameterBlock(k);
      fit->SetNumResiduals(static_cast<int>(weighted_projection.rows()));
      ceres::Problem map_problem;
      map_problem.AddResidualBlock(fit.release(), nullptr, x.data());
      // The total mass weighted like the beta residuals (relative), for conditioning.
      if (space.options().total_mass_constraint)
        map_problem.AddResidualBlock(totalMassCost(space, 1.0).release(), nullptr, x.data());
      if (eps > 0.0) {
        const Eigen::MatrixXd pull = eps * half_range.cwiseInverse().asDiagonal().toDenseMatrix();
        map_problem.AddResidualBlock(new LinearResidual(pull, pull * centre), nullptr, x.data());
      }
      for (int j = 0; j < k; ++j) {
        map_problem.SetParameterLowerBound(x.data(), j, space.lower()[j]);
        map_problem.SetParameterUpperBound(x.data(), j, space.upper()[j]);
      }
      ceres::Solver::Options map_solver;
      map_solver.linear_solver_type = ceres::DENSE_QR;
      map_solver.max_num_iterations = 200;
      map_solver.function_tolerance = 1e-20;
      map_solver.gradient_tolerance = 1e-24;
      map_solver.parameter_tolerance = 1e-16;
      map_solver.logging_type = ceres::SILENT;
      ceres::Solver::Summary map_summary;
      ceres::Solve(map_solver, &map_problem, &map_summary);
    }
    fit_cost[t] = (weighted_projection * space.standardAt(x) - weighted_target).squaredNorm();
    if (space.options().total_mass_constraint)
      fit_cost[t] += std::pow(space.totalMass(x) / space.options().total_mass - 1.0, 2);
    if (!std::isfinite(fit_cost[t])) fit_cost[t] = std::numeric_limits<double>::infinity();
  });
  const double best = fit_cost.minCoeff();
  const Eigen::VectorXd x_scale = magnitudes(result.x);
  int chosen = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (int t = 0; t < tries; ++t) {
    // "Best": within round-off of the lowest (b residuals of relative size ~1e-12).
    if (!(fit_cost[t] <= best * (1.0 + 1e-6) + 1e-24 * b)) continue;
    const double distance = (fitted[t] - result.x).cwiseQuotient(x_scale).norm();
    if (distance < nearest) nearest = distance, chosen = t;
  }
  const Eigen::VectorXd& x = fitted[chosen];
  result.map_back_error =
      (weights.cwiseProduct(P * space.standardAt(x) - beta)).norm() / std::sqrt(std::max(b, 1));
  // Keep the mapped-back point only when it predicts no worse than the start.
  const double gc_mapped = gcError(space.modelAt(x), problem, workspace, pool);
  result.map_back_used = std::isfinite(gc_mapped) && gc_mapped <= result.initial_gc;
  if (result.map_back_used) result.x = x;
}

}  // namespace

RefineResult refineGc(const ParameterSpace& space, const GcProblem& problem,
                      const Eigen::VectorXd& x0, const RefineOptions& options,
                      const BaseCoordinates* base) {
  const auto clock_start = std::chrono::steady_clock::now();
  if (x0.size() != space.numFree())
    throw InputError("the start has " + std::to_string(x0.size()) + " free parameters, expected " +
                     std::to_string(space.numFree()));
  if (space.numFree() == 0) throw InputError("refinement needs at least one free parameter");
  if (!std::isfinite(options.continuity_weight) || options.continuity_weight < 0.0)
    throw InputError("the continuity weight must be a finite number >= 0");
  RefineResult result;
  result.x = space.project(x0);
  const Model structure = space.modelAt(result.x);
  const int n = structure.numJoints(), segments = problem.numSegments();
  if (problem.data.numJoints() != n)
    throw InputError("the data has " + std::to_string(problem.data.numJoints()) +
                     " joints, the model " + std::to_string(n));
  if (base != nullptr && base->projection.cols() != structure.parameterLayout().size())
    throw InputError("the base coordinates have " + std::to_string(base->projection.cols()) +
                     " standard parameters, the model " +
                     std::to_string(structure.parameterLayout().size()));
  const bool with_start = options.estimate_initial_states;
  for (int s = 0; s < segments; ++s)
    if (continuityOf(problem, options, s) > 0.0) ++result.chained_segments;
  result.initial_states.resize(2 * n, segments);
  for (int s = 0; s < segments; ++s) {
    result.initial_states.col(s).head(n) = problem.data.q.col(problem.starts[s]);
    result.initial_states.col(s).tail(n) = problem.data.dq.col(problem.starts[s]);
  }
  ThreadPool pool(std::max(options.num_threads, 1));
  GcWorkspace workspace(structure, pool.numThreads());
  result.initial_gc = gcError(structure, problem, workspace, pool);

  if (base != nullptr && options.base_stage)
    baseStage(structure, space, problem, *base, options, clock_start, workspace, pool, result);

  // The parameter stage. Residual blocks: one per segment, and the total mass.
  ceres::Problem solver_problem;
  for (int s = 0; s < segments; ++s) {
    solver_problem.AddResidualBlock(
        makeSegmentCost(structure, space, problem, s, with_start, continuityOf(problem, options, s))
            .release(),
        nullptr, segmentBlocks(problem, options, s, result.x.data(), result.initial_states));
  }
  if (space.options().total_mass_constraint)
    solver_problem.AddResidualBlock(makeTotalMassCost(space).release(), nullptr, result.x.data());
  // Gauge: hold the current free directions (G (x - x_start) = 0, G their scaled basis), so the
  // solver does not drift along directions the data cannot see; a zero-residual point with the
  // gauge satisfied exists, so it biases nothing.
  if (base != nullptr && options.fix_gauge) {
    const FreeAnalysis analysis =
        analyseFreeDirections(structure, space, base->projection, result.x);
    const int free = space.numFree() - analysis.rank;
    if (free > 0) {
      const double w = std::sqrt(std::max(result.initial_gc, 1e-300));
      const Eigen::MatrixXd g =
          w * analysis.v.rightCols(free).transpose() * analysis.x_scale.cwiseInverse().asDiagonal();
      solver_problem.AddResidualBlock(new LinearResidual(g, g * result.x), nullptr,
                                      result.x.data());
      result.gauge_dimension = free;
    }
  }
  for (int j = 0; j < space.numFree(); ++j) {
    solver_problem.SetParameterLowerBound(result.x.data(), j, space.lower()[j]);
    solver_problem.SetParameterUpperBound(result.x.data(), j, space.upper()[j]);
  }
  ceres::Solver::Options solver =
      solverOptions(options, problem, result.x.data(), result.initial_states,
                    options.max_seconds - secondsSince(clock_start));
  result.linear_solver = ceres::LinearSolverTypeToString(solver.linear_solver_type);
  RefineCallback callback(result.history, options.stop, result.interrupted, "parameters",
                          secondsSince(clock_start));
  solver.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  if (!result.interrupted) ceres::Solve(solver, &solver_problem, &summary);

  result.termination = result.interrupted && summary.iterations.empty()
                           ? "USER_SUCCESS: interrupted in the base stage"
                           : terminationOf(summary);
  result.usable =
      result.interrupted && summary.iterations.empty() ? true : summary.IsSolutionUsable();
  result.iterations = std::max(static_cast<int>(summary.iterations.size()) - 1, 0);
  if (!result.base_stage) result.initial_cost = summary.initial_cost;
  result.final_cost = summary.iterations.empty() ? result.initial_cost : summary.final_cost;
  result.final_gc = gcError(space.modelAt(result.x), problem, workspace, pool);
  const std::vector<std::string> names = space.freeNames();
  for (int j = 0; j < space.numFree(); ++j) {
    const double tolerance = 1e-9 * (space.upper()[j] - space.lower()[j]);
    if (result.x[j] - space.lower()[j] <= tolerance || space.upper()[j] - result.x[j] <= tolerance)
      result.at_bound.push_back(names[j]);
  }
  if (base != nullptr) baseUncertainty(structure, space, problem, *base, options, result, pool);
  result.seconds = secondsSince(clock_start);
  return result;
}

}  // namespace dynid
