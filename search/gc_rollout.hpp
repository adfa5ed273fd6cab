// The one GC-error segment rollout, for any Scalar: gcError (double) and the refinement's cost
// functors (ceres::Jet) both call it, so the prediction they measure is the same code.
// For a Scalar other than double, include core/integrators-inl.hpp too (the integrators' bodies).
#pragma once

#include <array>
#include <type_traits>

#include "core/integrators.hpp"
#include "core/lanes.hpp"
#include "search/gc_problem.hpp"

namespace dynid {

/// Rolls segment `segment` of `problem` forward: on entry q, dq (n entries) hold the segment's
/// start state, on return its predicted end after problem.samples_per_segment sample periods,
/// each applying the recorded torque of its first sample (held, as recorded) over
/// problem.substeps integration steps of problem.step. `tau` (n entries) is scratch for the
/// torques in Scalar (untouched when Scalar is double: the recorded column is used directly).
/// Overwrites what the integrator overwrites in `data`. Sizes are the caller's to check.
template <typename Scalar>
void rollOutSegment(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data, const GcProblem& problem,
                    int segment, VectorX<Scalar>& q, VectorX<Scalar>& dq, VectorX<Scalar>& tau) {
  const Trajectory& recorded = problem.data;
  const int start = problem.starts[segment];
  const Scalar h(problem.step);
  for (int k = start; k < start + problem.samples_per_segment; ++k) {
    if constexpr (std::is_same_v<Scalar, double>) {
      for (int sub = 0; sub < problem.substeps; ++sub)
        integratorStep(problem.integrator, model, data, q, dq, recorded.tau.col(k), h);
    } else {
      // tau_k in Scalar, once per sample period.
      for (int j = 0; j < model.numJoints(); ++j) tau[j] = Scalar(recorded.tau(j, k));
      for (int sub = 0; sub < problem.substeps; ++sub)
        integratorStep(problem.integrator, model, data, q, dq, tau, h);
    }
  }
}

/// rollOutSegment for W segments at once, lane l rolling segment segments[l] (core/lanes.hpp): on
/// entry lane l of q, dq holds that segment's start state, on return its predicted end. `tau` (n
/// entries) is scratch. Each lane applies its own segment's recorded torques; the lanes share the
/// model, so they may repeat a segment (a last group with fewer than W left). Sizes are the
/// caller's to check. Needs core/integrators-inl.hpp (no Lanes instantiation is compiled in core).
template <int W, int Isa>
void rollOutSegments(const ModelTpl<Lanes<W, Isa>>& model, DataTpl<Lanes<W, Isa>>& data,
                     const GcProblem& problem, const std::array<int, W>& segments,
                     VectorX<Lanes<W, Isa>>& q, VectorX<Lanes<W, Isa>>& dq,
                     VectorX<Lanes<W, Isa>>& tau) {
  const Eigen::MatrixXd& recorded = problem.data.tau;
  std::array<int, W> starts;
  for (int l = 0; l < W; ++l) starts[l] = problem.starts[segments[l]];
  const Lanes<W, Isa> h(problem.step);
  for (int k = 0; k < problem.samples_per_segment; ++k) {
    // Lane l's tau: its segment's sample k, held over the sample period.
    for (int j = 0; j < model.numJoints(); ++j)
      for (int l = 0; l < W; ++l) tau[j].set(l, recorded(j, starts[l] + k));
    for (int sub = 0; sub < problem.substeps; ++sub)
      integratorStep(problem.integrator, model, data, q, dq, tau, h);
  }
}

}  // namespace dynid
