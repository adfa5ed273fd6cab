// Refinement of a GC-error estimate by nonlinear least squares (Ceres): the search's rough answer
// turned into the best answer the data allow, with exact derivatives. Three rooms: the cost
// functions (costs.hpp), the uncertainty in base coordinates (uncertainty.hpp) and this driver
// (stages, map back, solver settings); options and results in options.hpp. The residuals, stages
// and uncertainty are described in docs/REFINEMENT.md, "How the refinement works".
#pragma once

#include <Eigen/Core>

#include "core/parameters.hpp"
#include "search/gc_error.hpp"
#include "search/parameter_space.hpp"
#include "search/refinement/options.hpp"

namespace dynid {

/// Refines x0 (numFree() entries, projected onto the bounds first). `base` may be null (no
/// uncertainty, no base stage). `termination`, `usable` and `iterations` are the final stage's;
/// the time budget and the stop flag cover both. Throws InputError when the problem's joint count
/// differs from the space's model, x0 has the wrong size or the continuity weight is negative or
/// not finite.
RefineResult refineGc(const ParameterSpace& space, const GcProblem& problem,
                      const Eigen::VectorXd& x0, const RefineOptions& options,
                      const BaseCoordinates* base = nullptr);

/// Silences Ceres' own log lines (glog below FATAL, e.g. "Terminating: Residual and Jacobian
/// evaluation failed" when a budget or Ctrl-C ends a stage) for the whole process: for programs
/// such as the CLI that report every termination themselves. Libraries leave glog to their host.
void silenceSolverLog();

}  // namespace dynid
