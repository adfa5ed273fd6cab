// The refinement's Ceres cost functions (refine.hpp says what they measure): one GC segment's
// residuals under three parameterisations of the model (the search's free parameters x, the
// standard parameters theta, the base parameters beta), the maps theta(x) and beta(x) the map
// back fits, and the linear residuals (total mass, gauge). Every rollout is rollOutSegment
// (search/gc_rollout.hpp) in ceres::Jet, so the derivatives are exact.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/model.hpp"
#include "core/run_control.hpp"
#include "search/gc_error.hpp"
#include "search/parameter_space.hpp"
#include "search/refinement/options.hpp"

namespace ceres {
class CostFunction;
}

namespace dynid {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// theta = theta_ref + lift (beta - beta_ref), lift (p x b) a right inverse of P: the model at base
/// parameters beta.
struct BetaLift {
  Eigen::VectorXd theta_ref, beta_ref;
  Eigen::MatrixXd lift;
};

/// Segment `segment`'s residuals as a function of the free parameters x (parameter blocks: x,
/// then the start when `with_start`, then the next segment's start when `continuity` > 0, which
/// also needs `with_start`). The caller owns it; it refers to `space`, `problem` and `budget`.
/// Once `budget` (when given) is stopped, every residual evaluation (no Jacobian) fails at once,
/// so a solver iteration that runs past a time budget ends within one Jacobian evaluation.
std::unique_ptr<ceres::CostFunction> makeSegmentCost(const Model& structure,
                                                     const ParameterSpace& space,
                                                     const GcProblem& problem, int segment,
                                                     bool with_start, double continuity = 0.0,
                                                     const RunControl* budget = nullptr);
/// The same residuals as a function of beta (parameter block sizes as makeSegmentCost's, the
/// first of num_base entries).
std::unique_ptr<ceres::CostFunction> makeBetaSegmentCost(const Model& structure,
                                                         const BetaLift& lift,
                                                         const GcProblem& problem, int segment,
                                                         bool with_start, double continuity,
                                                         const RunControl* budget = nullptr);
/// theta(x) (p residuals, parameter block x): differentiated for the free directions.
std::unique_ptr<ceres::CostFunction> makeStandardOfFreeCost(const Model& structure,
                                                            const ParameterSpace& space);
/// W P theta(x) - W beta_target (num_base residuals, parameter block x): the map back.
std::unique_ptr<ceres::CostFunction> makeBetaOfFreeCost(const Model& structure,
                                                        const ParameterSpace& space,
                                                        Eigen::MatrixXd weighted_projection,
                                                        Eigen::VectorXd weighted_target);
/// r = A x - b (parameter block x, A.cols() entries).
std::unique_ptr<ceres::CostFunction> makeLinearCost(Eigen::MatrixXd a, Eigen::VectorXd b);
/// w (fixed mass + sum of free masses - total), w = 1 / (tolerance total): the total mass held to
/// about `tolerance` relative (parameter block x).
std::unique_ptr<ceres::CostFunction> makeTotalMassCost(const ParameterSpace& space,
                                                       double tolerance = 1e-6);

// How segments chain (RefineOptions::continuity_weight).
/// The segment that starts where segment s ends, or -1.
int nextSegment(const GcProblem& problem, int s);
/// The continuity weight of segment s's end residual: > 0 when it ends on the next start.
double continuityOf(const GcProblem& problem, const RefineOptions& options, int s);
/// Whether any segment ends on the next one's start (the starts are then not independent).
bool anyChained(const GcProblem& problem, const RefineOptions& options);
/// The parameter blocks of segment s's residuals: `model_block`, then its start and the next
/// segment's start as needed (pointers into `starts`, 2n x segments).
std::vector<double*> segmentBlocks(const GcProblem& problem, const RefineOptions& options, int s,
                                   double* model_block, Eigen::MatrixXd& starts);

}  // namespace dynid
