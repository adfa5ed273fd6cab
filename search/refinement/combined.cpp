#include "search/refinement/combined.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/QR>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/integrators-inl.hpp"
#include "core/parallel.hpp"
#include "core/rnea.hpp"
#include "core/signal.hpp"
#include "search/gc_error.hpp"
#include "search/refinement/costs.hpp"

namespace dynid {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The GC residuals at theta and their Jacobian in theta (J_beta P), segment by segment; false
/// when a rollout diverges or `control` stops (checked before every segment).
bool linearise(const Model& structure, const GcProblem& problem, const Eigen::MatrixXd& P,
               const Eigen::MatrixXd& lift, const Eigen::VectorXd& theta, ThreadPool& pool,
               const RunControl& control, Eigen::VectorXd* r, Eigen::MatrixXd* J) {
  const int n = structure.numJoints(), b = static_cast<int>(P.rows());
  const int segments = problem.numSegments();
  const BetaLift map{theta, P * theta, lift};
  r->resize(2 * n * segments);
  Eigen::MatrixXd j_beta(2 * n * segments, b);
  std::vector<char> ok(segments, 1);
  pool.parallelFor(segments, [&](int s, int) {
    if (control.stopped()) {
      ok[s] = 0;
      return;
    }
    const auto cost = makeBetaSegmentCost(structure, map, problem, s, false, 0.0);
    RowMajorMatrix js(2 * n, b);
    Eigen::VectorXd rs(2 * n);
    const double* parameters[1] = {map.beta_ref.data()};
    double* jacobians[1] = {js.data()};
    ok[s] = cost->Evaluate(parameters, rs.data(), jacobians) && rs.allFinite() && js.allFinite();
    r->segment(2 * n * s, 2 * n) = rs;
    j_beta.middleRows(2 * n * s, 2 * n) = js;
  });
  if (std::find(ok.begin(), ok.end(), 0) != ok.end()) return false;
  *J = j_beta * P;
  return true;
}

Model modelAt(const Model& structure, const Eigen::VectorXd& theta) {
  Model m = structure;
  m.setStandardParameters(theta);
  return m;
}

/// The GC term's shape: g(G) = G - G_f log G above the noise floor G_f, flat below it (G itself
/// without a floor): continuously differentiable, its slope falling to 0 at the floor, so lowering
/// the GC error below what the torque noise alone causes gains nothing and the torque term holds
/// the estimate there.
double gcShape(double g, double floor) {
  if (!(floor > 0.0)) return g;
  return g > floor ? g - floor * std::log(g) : floor - floor * std::log(floor);
}

/// Phi's parts at theta; the GC part is NaN when `control` stopped the evaluation.
CombinedValue valueAt(const TorqueTerm& torque, const GcTerm& gc, const Eigen::VectorXd& theta,
                      double w, double g0, double floor, const RunControl& control) {
  CombinedValue v;
  v.torque = torque.cost(theta) / torque.scale;
  if (!std::isfinite(v.torque)) {
    v.cost = v.gc = std::numeric_limits<double>::infinity();
    return v;
  }
  v.gc = gc.error(theta, control);
  v.cost = v.torque + w * gcShape(0.5 * v.gc, floor) / g0;
  return v;
}

/// The fixed-base GC term: a GcProblem's rollouts on dynid's pool, the Jacobian by Ceres's
/// automatic differentiation in the base parameters (linearise above).
GcTerm fixedGcTerm(const Model& structure, const GcProblem& problem, const BaseCoordinates& base,
                   const CombinedOptions& options) {
  struct Shared {
    explicit Shared(int threads) : pool(threads), workspace(pool.numThreads()) {}
    ThreadPool pool;
    GcWorkspace workspace;
    Eigen::MatrixXd lift;
  };
  const auto shared = std::make_shared<Shared>(std::max(options.num_threads, 1));
  if (base.projection.size() > 0)  // none for a value alone (combinedValue)
    shared->lift = base.projection.completeOrthogonalDecomposition().pseudoInverse();
  const Eigen::MatrixXd P = base.projection;
  GcTerm out;
  out.error = [&structure, &problem, shared](const Eigen::VectorXd& theta,
                                             const RunControl& control) {
    return gcError(modelAt(structure, theta), problem, shared->workspace, shared->pool, control);
  };
  out.linearise = [&structure, &problem, shared, P](const Eigen::VectorXd& theta,
                                                    const RunControl& control, Eigen::VectorXd* r,
                                                    Eigen::MatrixXd* J) {
    return linearise(structure, problem, P, shared->lift, theta, shared->pool, control, r, J);
  };
  const int draws = options.floor_draws, threads = options.num_threads;
  out.floor = [&structure, &problem, draws, threads](const Eigen::VectorXd& theta0) {
    return gcNoiseFloor(modelAt(structure, theta0), problem, draws, threads);
  };
  return out;
}

void checkInputs(const Model& structure, const GcProblem& problem, const BaseCoordinates& base,
                 const Eigen::VectorXd& theta) {
  const int p = structure.parameterLayout().size();
  if (theta.size() != p)
    throw InputError("the start has " + std::to_string(theta.size()) + " parameters, expected " +
                     std::to_string(p));
  if (base.projection.cols() != p)
    throw InputError("the base coordinates have " + std::to_string(base.projection.cols()) +
                     " standard parameters, the model " + std::to_string(p));
  if (problem.data.numJoints() != structure.numJoints())
    throw InputError("the data has " + std::to_string(problem.data.numJoints()) +
                     " joints, the model " + std::to_string(structure.numJoints()));
}

void checkTerms(const TorqueTerm& torque, double gc_weight) {
  if (!(gc_weight >= 0.0) || !std::isfinite(gc_weight))
    throw InputError("the GC weight must be finite and >= 0");
  if (!(torque.scale > 0.0) || !std::isfinite(torque.scale))
    throw InputError("the torque term's scale must be finite and > 0");
  if (!torque.cost || !torque.derivatives) throw InputError("the torque term is not set");
}

/// Phi's gradient and Gauss-Newton Hessian at theta from the GC residuals r and their Jacobian J
/// in theta there (unused when w = 0): F's exact derivatives / T0, plus, above the floor,
/// d g(G) = (1 - G_f / G) dG with Hessian (1 - G_f / G) J^T J + (G_f / G^2) (J^T r)(J^T r)^T;
/// below it, nothing. `floor` and `g0` in G's units (GC / 2).
void quadraticModel(const TorqueTerm& torque, const Eigen::VectorXd& theta,
                    const Eigen::VectorXd& r, const Eigen::MatrixXd& J, double w, double g0,
                    double floor, Eigen::VectorXd* g, Eigen::MatrixXd* H) {
  torque.derivatives(theta, g, H);
  *g /= torque.scale;
  *H /= torque.scale;
  if (!(w > 0.0)) return;
  const double G = 0.5 * r.squaredNorm(), c = w / g0;
  if (!(G > floor)) return;
  const Eigen::VectorXd jr = J.transpose() * r;
  *g += c * (1.0 - floor / G) * jr;
  *H += c * (1.0 - floor / G) * (J.transpose() * J);
  if (floor > 0.0) *H += c * floor / (G * G) * (jr * jr.transpose());
}

}  // namespace

namespace {

/// The residual's noise level per joint: half the mean squared first difference (white noise of
/// variance s^2 has differences of variance 2 s^2; a smooth model error has almost none).
Eigen::VectorXd residualNoise(const Model& model, const Trajectory& data) {
  const int n = model.numJoints(), samples = data.numSamples();
  Eigen::VectorXd sigma = Eigen::VectorXd::Zero(n), previous(n), residual(n);
  Data d(model);
  for (int k = 0; k < samples; ++k) {
    residual = data.tau.col(k) - rnea(model, d, data.q.col(k), data.dq.col(k), data.ddq.col(k));
    if (k > 0) sigma += (residual - previous).cwiseAbs2();
    previous = residual;
  }
  return (sigma / (2.0 * std::max(samples - 1, 1))).cwiseSqrt();
}

/// The draws of filtered noise: per draw, white noise of `noise.sigma` over the whole log, each
/// joint low-passed zero-phase, each segment's slice at (s draws + k) length.
Eigen::MatrixXd filteredDraws(const TorqueNoise& noise, const GcProblem& problem, int draws,
                              std::mt19937_64& random) {
  const int n = static_cast<int>(noise.sigma.size()), samples = problem.data.numSamples();
  const int length = problem.samples_per_segment, segments = problem.numSegments();
  std::normal_distribution<double> normal(0.0, 1.0);
  const std::vector<Biquad> filter = butterworthLowPass(noise.order, noise.cutoff, noise.rate);
  Eigen::MatrixXd out(n, static_cast<Eigen::Index>(segments) * draws * length);
  Eigen::VectorXd white(samples);
  for (int k = 0; k < draws; ++k)
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < samples; ++i) white[i] = noise.sigma[j] * normal(random);
      filtfiltInPlace(filter, white);
      for (int s = 0; s < segments; ++s)
        out.row(j).segment((static_cast<Eigen::Index>(s) * draws + k) * length, length) =
            white.segment(problem.starts[s], length).transpose();
    }
  return out;
}

}  // namespace

double gcNoiseFloor(const Model& model, const GcProblem& problem, int draws, int num_threads,
                    const TorqueNoise* given) {
  const Trajectory& data = problem.data;
  const int n = model.numJoints(), samples = data.numSamples();
  const int length = problem.samples_per_segment, segments = problem.numSegments();
  if (data.numJoints() != n)
    throw InputError("the data has " + std::to_string(data.numJoints()) + " joints, the model " +
                     std::to_string(n));
  if (given != nullptr && given->sigma.size() != n)
    throw InputError("the torque noise has " + std::to_string(given->sigma.size()) +
                     " joints, the model " + std::to_string(n));
  if (draws < 1 || segments == 0 || samples < length) return 0.0;
  // The draws: fixed seed, drawn in order, so the floor is the same for any thread count.
  std::mt19937_64 random(20261126);
  Eigen::MatrixXd noise;
  if (given != nullptr && given->order > 0) {
    noise = filteredDraws(*given, problem, draws, random);
  } else {
    const Eigen::VectorXd sigma = given != nullptr ? given->sigma : residualNoise(model, data);
    std::normal_distribution<double> normal(0.0, 1.0);
    noise.resize(n, static_cast<Eigen::Index>(segments) * draws * length);
    for (Eigen::Index k = 0; k < noise.cols(); ++k)
      for (int j = 0; j < n; ++j) noise(j, k) = sigma[j] * normal(random);
  }
  Eigen::VectorXd per_segment = Eigen::VectorXd::Zero(segments);
  ThreadPool pool(std::max(num_threads, 1));
  pool.parallelFor(segments, [&](int s, int) {
    Data d(model);
    const int start = problem.starts[s];
    const auto roll = [&](Eigen::Index first) {  // the end state under tau (+ noise from first)
      Eigen::VectorXd q = data.q.col(start), dq = data.dq.col(start), tau(n);
      for (int k = 0; k < length; ++k) {
        tau = data.tau.col(start + k);
        if (first >= 0) tau += noise.col(first + k);
        for (int sub = 0; sub < problem.substeps; ++sub)
          integratorStep(problem.integrator, model, d, q, dq, tau, problem.step);
      }
      Eigen::VectorXd out(2 * n);
      out << q.cwiseProduct(problem.weight_q), dq.cwiseProduct(problem.weight_dq);
      return out;
    };
    const Eigen::VectorXd clean = roll(-1);
    double sum = 0.0;
    for (int k = 0; k < draws; ++k) {
      const double e =
          (roll((static_cast<Eigen::Index>(s) * draws + k) * length) - clean).squaredNorm();
      sum += std::isfinite(e) ? std::min(e, kMaxSegmentError) : kMaxSegmentError;
    }
    per_segment[s] = sum / draws;
  });
  return per_segment.sum();
}

CombinedValue combinedValue(const Model& structure, const GcProblem& problem,
                            const TorqueTerm& torque, const Eigen::VectorXd& theta,
                            double gc_weight, double gc_scale, double gc_floor, int num_threads) {
  CombinedOptions options;
  options.num_threads = num_threads;
  const GcTerm gc = fixedGcTerm(structure, problem, BaseCoordinates{}, options);
  return valueAt(torque, gc, theta, gc_weight, gc_scale, 0.5 * gc_floor, {});
}

Eigen::VectorXd combinedGradientTerms(const TorqueTerm& torque, const GcTerm& gc,
                                      const Eigen::VectorXd& theta, double gc_weight,
                                      double gc_scale, double gc_floor) {
  checkTerms(torque, gc_weight);
  Eigen::VectorXd r, g;
  Eigen::MatrixXd J, H;
  if (!gc.linearise(theta, {}, &r, &J)) throw NumericalError("a GC rollout diverged");
  quadraticModel(torque, theta, r, J, gc_weight, gc_scale, 0.5 * gc_floor, &g, &H);
  return g;
}

Eigen::VectorXd combinedGradient(const Model& structure, const GcProblem& problem,
                                 const BaseCoordinates& base, const TorqueTerm& torque,
                                 const Eigen::VectorXd& theta, double gc_weight, double gc_scale,
                                 double gc_floor, int num_threads) {
  checkInputs(structure, problem, base, theta);
  CombinedOptions options;
  options.num_threads = num_threads;
  return combinedGradientTerms(torque, fixedGcTerm(structure, problem, base, options), theta,
                               gc_weight, gc_scale, gc_floor);
}

namespace {

/// The combined estimate at its start theta0: the GC error (refused when it predicts no usable
/// motion), its scale and noise floor, the cost (`current`) and the history's first row.
CombinedResult startOfCombined(const TorqueTerm& torque, const GcTerm& gc,
                               const Eigen::VectorXd& theta0, const CombinedOptions& options,
                               Clock::time_point t0, CombinedValue& current) {
  const double w = options.gc_weight;
  CombinedResult out;
  out.theta = theta0;
  out.initial_gc = gc.error(theta0, {});
  if (!std::isfinite(out.initial_gc) || out.initial_gc >= kMaxSegmentError ||
      !(out.initial_gc > 0.0))
    throw NumericalError("the combined estimator's start predicts no usable motion (GC error " +
                         formatNumber(out.initial_gc, 3, "n/a") + ")");
  out.gc_scale = 0.5 * (options.given_gc > 0.0 ? options.given_gc : out.initial_gc);
  out.gc_weight = w;
  if (options.noise_floor && w > 0.0)
    out.gc_floor = options.given_floor >= 0.0 ? options.given_floor
                   : gc.floor                 ? gc.floor(theta0)
                                              : 0.0;
  const double floor = 0.5 * out.gc_floor;  // in G = GC / 2
  current = CombinedValue{0.0, torque.cost(theta0) / torque.scale, out.initial_gc};
  current.cost = current.torque + w * gcShape(0.5 * current.gc, floor) / out.gc_scale;
  out.initial_cost = current.cost;
  out.initial_torque = current.torque;
  out.history.push_back({0, current.cost, current.torque, current.gc, 0.0, since(t0)});
  return out;
}

/// The damped step (H + mu diag(H)) delta = -g and the decrease the quadratic model predicts for
/// it; false when the step is no descent (a failed factorisation included).
bool dampedStep(const Eigen::MatrixXd& H, const Eigen::VectorXd& g, double mu,
                Eigen::VectorXd& delta, double& predicted) {
  Eigen::VectorXd diagonal = H.diagonal().cwiseMax(1e-12 * H.diagonal().cwiseAbs().maxCoeff());
  Eigen::MatrixXd damped = H;
  damped.diagonal() += mu * diagonal;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(damped);
  delta = ldlt.solve(-g);
  predicted = -(g.dot(delta) + 0.5 * delta.dot(H * delta));
  return ldlt.info() == Eigen::Success && delta.allFinite() && predicted > 0.0;
}

/// The estimator's inputs: set terms, a finite weight and normalisers, a start inside F's domain.
void checkStart(const TorqueTerm& torque, const GcTerm& gc, const Eigen::VectorXd& theta0,
                const CombinedOptions& options) {
  checkTerms(torque, options.gc_weight);
  if (!gc.error || !gc.linearise) throw InputError("the GC term is not set");
  if (!(options.given_gc >= 0.0) || !std::isfinite(options.given_gc) ||
      !std::isfinite(options.given_floor))
    throw InputError(
        "the given GC normaliser and noise floor must be finite (and the normaliser "
        ">= 0)");
  if (!std::isfinite(torque.cost(theta0)))
    throw InputError("the combined estimator's start is outside the physical set");
}

/// One progress line after an accepted step.
void sayProgress(const CombinedOptions& options, const CombinedResult& out,
                 const CombinedValue& current) {
  if (!options.control.progress) return;
  const double elapsed = out.history.back().seconds;
  double done = static_cast<double>(out.iterations) / std::max(options.max_iterations, 1);
  if (options.max_seconds > 0.0) done = std::max(done, elapsed / options.max_seconds);
  options.control.say("combined iteration " + std::to_string(out.iterations) + ": cost " +
                      formatNumber(current.cost, 4) + " (torque " +
                      formatNumber(current.torque, 4) + ", GC error " +
                      formatNumber(current.gc, 4) + "); " + progressText(done, elapsed));
}

}  // namespace

CombinedResult refineCombined(const Model& structure, const GcProblem& problem,
                              const BaseCoordinates& base, const TorqueTerm& torque,
                              const Eigen::VectorXd& theta0, const CombinedOptions& options) {
  checkInputs(structure, problem, base, theta0);
  return refineCombinedTerms(torque, fixedGcTerm(structure, problem, base, options), theta0,
                             options);
}

CombinedResult refineCombinedTerms(const TorqueTerm& torque, const GcTerm& gc,
                                   const Eigen::VectorXd& theta0, const CombinedOptions& options) {
  const auto t0 = Clock::now();
  checkStart(torque, gc, theta0, options);
  const RunControl control = options.control.within(options.max_seconds, t0);
  const double w = options.gc_weight;
  CombinedValue current;
  CombinedResult out = startOfCombined(torque, gc, theta0, options, t0, current);
  const double floor = 0.5 * out.gc_floor;  // in G = GC / 2

  const auto stop = [&](const std::string& why) {
    out.interrupted = true;
    out.termination = "USER_SUCCESS: " + why;
  };
  double mu = 1e-3;  // Marquardt's damping, relative to the diagonal
  Eigen::VectorXd r, g;
  Eigen::MatrixXd J, H;
  bool fresh = false;  // r, J, g, H are at out.theta
  while (out.termination.empty()) {
    if (control.check()) {
      stop(options.control.stopped() ? "stopped (interrupt or the run's deadline)"
                                     : "stopped at its time budget");
      break;
    }
    if (!fresh) {
      if (out.iterations >= options.max_iterations) {
        out.termination = "NO_CONVERGENCE: Maximum number of iterations reached (" +
                          std::to_string(options.max_iterations) + ")";
        break;
      }
      // With w = 0 the GC term has no say: F's derivatives alone.
      if (w > 0.0 && !gc.linearise(out.theta, control, &r, &J)) {
        if (control.stopped()) continue;  // the stop is reported at the loop's top
        out.termination = "NO_CONVERGENCE: a GC rollout diverged at the current estimate";
        break;
      }
      ++out.iterations;
      quadraticModel(torque, out.theta, r, J, w, out.gc_scale, floor, &g, &H);
      fresh = true;
    }
    Eigen::VectorXd delta;
    double predicted = 0.0;
    if (!dampedStep(H, g, mu, delta, predicted)) {
      if (mu > 1e12) {
        out.termination = "CONVERGENCE: no descent direction left (gradient " +
                          formatNumber(g.norm(), 3, "n/a") + ")";
        break;
      }
      mu *= 10.0;
      continue;
    }
    const Eigen::VectorXd trial = out.theta + delta;
    const CombinedValue next = valueAt(torque, gc, trial, w, out.gc_scale, floor, control);
    if (std::isnan(next.gc) && control.stopped()) continue;
    const double actual = current.cost - next.cost;
    const double ratio = std::isfinite(next.cost) && next.gc < kMaxSegmentError
                             ? actual / predicted
                             : -std::numeric_limits<double>::infinity();
    if (ratio > 1e-3) {
      out.theta = trial;
      current = next;
      fresh = false;
      out.moved = true;
      out.history.push_back(
          {out.iterations, current.cost, current.torque, current.gc, mu, since(t0)});
      sayProgress(options, out, current);
      mu = std::max(mu * std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * ratio - 1.0, 3)), 1e-12);
      if (actual < options.function_tolerance * std::abs(current.cost))
        out.termination = "CONVERGENCE: the cost fell by less than " +
                          formatNumber(options.function_tolerance, 3, "n/a") + " relative";
    } else {
      mu *= 4.0;
      if (mu > 1e12)
        out.termination =
            "CONVERGENCE: no step lowers the cost (damping " + formatNumber(mu, 3, "n/a") + ")";
    }
  }
  out.final_cost = current.cost;
  out.final_torque = current.torque;
  out.final_gc = current.gc;
  out.seconds = since(t0);
  return out;
}

}  // namespace dynid
