#include "search/refinement/costs.hpp"

#include <algorithm>
#include <string>
#include <type_traits>

#include <ceres/ceres.h>

#include "core/errors.hpp"
#include "core/integrators-inl.hpp"
#include "core/model-inl.hpp"
#include "core/parallel.hpp"
#include "search/gc_rollout.hpp"
#include "search/refinement/gc_jacobian.hpp"

namespace dynid {

namespace {

// Jet width of the automatic differentiation passes: DynamicAutoDiffCostFunction differentiates
// this many parameters per rollout.
constexpr int kStride = 8;

using RowMajor = RowMajorMatrix;

/// Model parameters from the search's free parameters x.
struct FreeMap {
  const ParameterSpace* space;
  template <typename T>
  void apply(const T* x, ModelTpl<T>& model) const {
    std::vector<RigidInertia<T>> inertias;
    space->linkInertiasAt(x, inertias);
    model.setLinkInertias(inertias);
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
  BetaLift lift_map;
  template <typename T>
  void apply(const T* beta, ModelTpl<T>& model) const {
    const BetaLift& m = lift_map;
    VectorX<T> theta = m.theta_ref.cast<T>();
    for (int j = 0; j < m.beta_ref.size(); ++j) {
      const T delta = beta[j] - m.beta_ref[j];
      for (int k = 0; k < theta.size(); ++k)
        if (m.lift(k, j) != 0.0) theta[k] += m.lift(k, j) * delta;
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
  const RunControl* budget;  // null: none; once stopped, every evaluation fails at once

  template <typename T>
  bool operator()(T const* const* blocks, T* residuals) const {
    using std::isfinite;
    // Once stopped (Ctrl-C, the budget), every evaluation fails at once: a trial step is rejected,
    // a Jacobian ends the solve (FAILURE, silent: the solver logs nothing) and Ceres leaves the
    // parameters at the last accepted iterate (update_state_every_iteration; refine.cpp reports
    // such an end as a stop, not a failure). A stop so waits for one segment's rollout, not for
    // a whole Jacobian.
    if (budget != nullptr && budget->stopped()) return false;
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
    rollOutSegment(model, data, *problem, segment, q, dq, tau);
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
                                                 double continuity = 0.0,
                                                 const RunControl* budget = nullptr) {
  const int n = structure.numJoints();
  if (!with_start) continuity = 0.0;
  auto cost = std::make_unique<ceres::DynamicAutoDiffCostFunction<SegmentFunctor<Map>, kStride>>(
      new SegmentFunctor<Map>{structure, map, &problem, segment, with_start, continuity, budget});
  cost->AddParameterBlock(map_size);
  if (with_start) cost->AddParameterBlock(2 * n);
  if (continuity > 0.0) cost->AddParameterBlock(2 * n);
  cost->SetNumResiduals((with_start ? 4 : 2) * n);
  return cost;
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

}  // namespace

std::unique_ptr<ceres::CostFunction> makeSegmentCost(const Model& structure,
                                                     const ParameterSpace& space,
                                                     const GcProblem& problem, int segment,
                                                     bool with_start, double continuity,
                                                     const RunControl* budget) {
  return segmentCost(structure, FreeMap{&space}, space.numFree(), problem, segment, with_start,
                     continuity, budget);
}

std::unique_ptr<ceres::CostFunction> makeBetaSegmentCost(const Model& structure,
                                                         const BetaLift& lift,
                                                         const GcProblem& problem, int segment,
                                                         bool with_start, double continuity,
                                                         const RunControl* budget) {
  return segmentCost(structure, BetaMap{lift}, static_cast<int>(lift.beta_ref.size()), problem,
                     segment, with_start, continuity, budget);
}

std::unique_ptr<ceres::CostFunction> makeStandardOfFreeCost(const Model& structure,
                                                            const ParameterSpace& space) {
  auto cost = std::make_unique<ceres::DynamicAutoDiffCostFunction<StandardOfFree, kStride>>(
      new StandardOfFree{structure, FreeMap{&space}});
  cost->AddParameterBlock(space.numFree());
  cost->SetNumResiduals(structure.parameterLayout().size());
  return cost;
}

std::unique_ptr<ceres::CostFunction> makeBetaOfFreeCost(const Model& structure,
                                                        const ParameterSpace& space,
                                                        Eigen::MatrixXd weighted_projection,
                                                        Eigen::VectorXd weighted_target) {
  const int rows = static_cast<int>(weighted_projection.rows());
  auto cost =
      std::make_unique<ceres::DynamicAutoDiffCostFunction<BetaOfFree, kStride>>(new BetaOfFree{
          structure, FreeMap{&space}, std::move(weighted_projection), std::move(weighted_target)});
  cost->AddParameterBlock(space.numFree());
  cost->SetNumResiduals(rows);
  return cost;
}

std::unique_ptr<ceres::CostFunction> makeLinearCost(Eigen::MatrixXd a, Eigen::VectorXd b) {
  return std::make_unique<LinearResidual>(std::move(a), std::move(b));
}

std::unique_ptr<ceres::CostFunction> makeTotalMassCost(const ParameterSpace& space,
                                                       double tolerance) {
  const double total = space.options().total_mass;
  const double w = 1.0 / (tolerance * std::max(std::abs(total), 1e-12));
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(1, space.numFree());
  for (int p : space.massPositions()) a(0, p) = w;
  return std::make_unique<LinearResidual>(
      a, Eigen::VectorXd::Constant(1, w * (total - space.fixedMass())));
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

int nextSegment(const GcProblem& problem, int s) {
  if (s + 1 >= problem.numSegments()) return -1;
  return problem.starts[s + 1] == problem.starts[s] + problem.samples_per_segment ? s + 1 : -1;
}

double continuityOf(const GcProblem& problem, const RefineOptions& options, int s) {
  if (!options.estimate_initial_states || options.continuity_weight <= 0.0) return 0.0;
  return nextSegment(problem, s) >= 0 ? options.continuity_weight : 0.0;
}

bool anyChained(const GcProblem& problem, const RefineOptions& options) {
  for (int s = 0; s < problem.numSegments(); ++s)
    if (continuityOf(problem, options, s) > 0.0) return true;
  return false;
}

std::vector<double*> segmentBlocks(const GcProblem& problem, const RefineOptions& options, int s,
                                   double* model_block, Eigen::MatrixXd& starts) {
  std::vector<double*> blocks{model_block};
  if (options.estimate_initial_states) blocks.push_back(starts.col(s).data());
  if (continuityOf(problem, options, s) > 0.0) blocks.push_back(starts.col(s + 1).data());
  return blocks;
}

}  // namespace dynid
