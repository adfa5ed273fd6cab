#include "search/floating/floating_combined.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <Eigen/QR>

#include "core/errors.hpp"

namespace dynid {
namespace {

/// What the term's calls share: the segments, the lift and a pool.
struct FloatingTermState {
  FloatingTermState(const FloatingModel& structure, const FloatingGcData& data,
                    const FloatingGcOptions& options, const Eigen::MatrixXd& projection,
                    int threads)
      : structure(structure),
        data(data),
        segments(floatingGcSegments(structure, data, options)),
        substeps(options.substeps),
        P(projection),
        lift(projection.completeOrthogonalDecomposition().pseudoInverse()),
        pool(std::max(threads, 0)) {}

  FloatingModel at(const Eigen::VectorXd& theta) const {
    FloatingModel out = structure;
    out.setStandardParameters(theta);
    return out;
  }

  const FloatingModel& structure;
  const FloatingGcData& data;
  const FloatingGcResult segments;
  const int substeps;
  const Eigen::MatrixXd P, lift;
  ThreadPool pool;
};

/// The GC error of the residual columns, summed as floatingGcError sums its segments.
double errorOf(const Eigen::MatrixXd& residuals) {
  Eigen::VectorXd errors(residuals.cols());
  for (Eigen::Index i = 0; i < residuals.cols(); ++i)
    errors[i] = floatingSegmentError(residuals.col(i));
  return errors.sum();
}

/// r at theta (the columns stacked) and J = J_beta P; false when a rollout diverges or `control`
/// stops (checked before each direction's rollouts).
bool lineariseFloating(FloatingTermState& state, const Eigen::VectorXd& theta,
                       const RunControl& control, Eigen::VectorXd* r, Eigen::MatrixXd* J) {
  const Eigen::MatrixXd r0 =
      floatingGcResiduals(state.at(theta), state.data, state.segments, state.substeps, &state.pool);
  if (!r0.allFinite() || control.stopped()) return false;
  *r = Eigen::Map<const Eigen::VectorXd>(r0.data(), r0.size());
  const Eigen::VectorXd beta = state.P * theta;
  const double largest = beta.lpNorm<Eigen::Infinity>();
  const int b = static_cast<int>(state.P.rows());
  Eigen::MatrixXd j_beta(r->size(), b);
  std::vector<char> ok(static_cast<std::size_t>(b), 1);
  state.pool.parallelFor(b, [&](int i, int) {
    if (control.stopped()) {
      ok[static_cast<std::size_t>(i)] = 0;
      return;
    }
    const double h = 1e-6 * std::max(std::abs(beta[i]), 1e-6 * largest);
    const Eigen::MatrixXd ri = floatingGcResiduals(state.at(theta + h * state.lift.col(i)),
                                                   state.data, state.segments, state.substeps);
    ok[static_cast<std::size_t>(i)] = ri.allFinite();
    j_beta.col(i) = (Eigen::Map<const Eigen::VectorXd>(ri.data(), ri.size()) - *r) / h;
  });
  if (std::find(ok.begin(), ok.end(), 0) != ok.end()) return false;
  *J = j_beta * state.P;
  return true;
}

}  // namespace

GcTerm floatingGcTerm(const FloatingModel& structure, const FloatingGcData& data,
                      const FloatingGcOptions& options, const Eigen::MatrixXd& projection,
                      int num_threads) {
  if (projection.cols() != structure.numParameters())
    throw InputError("`projection` has " + std::to_string(projection.cols()) +
                     " columns, the floating model " + std::to_string(structure.numParameters()) +
                     " parameters");
  const auto state =
      std::make_shared<FloatingTermState>(structure, data, options, projection, num_threads);
  GcTerm out;
  out.error = [state](const Eigen::VectorXd& theta, const RunControl& control) {
    if (control.stopped()) return std::nan("");
    return errorOf(floatingGcResiduals(state->at(theta), state->data, state->segments,
                                       state->substeps, &state->pool));
  };
  out.linearise = [state](const Eigen::VectorXd& theta, const RunControl& control,
                          Eigen::VectorXd* r, Eigen::MatrixXd* J) {
    return lineariseFloating(*state, theta, control, r, J);
  };
  return out;
}

}  // namespace dynid
