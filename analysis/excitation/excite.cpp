#include "analysis/excitation/excite.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <random>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/crba.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/kinematics.hpp"
#include "core/memory.hpp"
#include "core/option_ranges.hpp"
#include "core/parallel.hpp"
#include "core/parameters.hpp"
#include "core/regressor.hpp"
#include "core/rnea.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"
#include "search/cobyla.hpp"
#include "search/gc_error.hpp"
#include "search/refinement/gc_jacobian.hpp"

namespace dynid {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// The optimiser keeps this fraction of every limit on its coarse grid; the check at check_rate
/// then shrinks the design if a peak between grid points still crosses a limit.
constexpr double kGridMargin = 0.99;

/// Objective of a rank-deficient or non-finite design: worse than any real one (log cond <= 37
/// in double precision).
constexpr double kInfeasibleObjective = 1e3;

std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// Sine and cosine of every harmonic on a time grid: the design's q, dq, ddq are then products.
struct Grid {
  Eigen::VectorXd time;
  Eigen::MatrixXd sine, cosine;  // H x M
  Grid(double period, int harmonics, int points, bool closed) {
    time.resize(points);
    const double step = period / (closed ? points - 1 : points);
    for (int m = 0; m < points; ++m) time[m] = m * step;
    if (closed) time[points - 1] = period;
    sine.resize(harmonics, points);
    cosine.resize(harmonics, points);
    const double w = kTwoPi / period;
    for (int k = 0; k < harmonics; ++k)
      for (int m = 0; m < points; ++m) {
        sine(k, m) = std::sin(w * (k + 1) * time[m]);
        cosine(k, m) = std::cos(w * (k + 1) * time[m]);
      }
  }
  int points() const { return static_cast<int>(time.size()); }
};

/// q, dq, ddq of a design on a grid (n x M each).
void motionOnGrid(const FourierSeries& d, const Grid& g, Eigen::MatrixXd& q, Eigen::MatrixXd& dq,
                  Eigen::MatrixXd& ddq) {
  const int n = d.numJoints(), h = d.harmonics();
  const double w = kTwoPi / d.period;
  Eigen::MatrixXd aq(n, h), bq(n, h), aa(n, h), ba(n, h);
  for (int k = 0; k < h; ++k) {
    const double wk = w * (k + 1);
    aq.col(k) = d.a.col(k) / wk;
    bq.col(k) = -d.b.col(k) / wk;
    aa.col(k) = -d.a.col(k) * wk;
    ba.col(k) = d.b.col(k) * wk;
  }
  q.noalias() = aq * g.sine + bq * g.cosine;
  q.colwise() += d.offset;
  dq.noalias() = d.a * g.cosine + d.b * g.sine;
  ddq.noalias() = aa * g.sine + ba * g.cosine;
}

Trajectory sampleOn(const FourierSeries& d, const Model& model, const Grid& g) {
  Trajectory t;
  t.time = g.time;
  motionOnGrid(d, g, t.q, t.dq, t.ddq);
  t.tau.resize(d.numJoints(), g.points());
  Data data(model);
  for (int m = 0; m < g.points(); ++m)
    t.tau.col(m) = rnea(model, data, t.q.col(m), t.dq.col(m), t.ddq.col(m));
  return t;
}

/// The design's free variables, scaled so that 1 is about a limit: per joint the offset (when
/// optimised) as a fraction of the half range about the middle, then a_j1..a_j(H-1) and
/// b_j1..b_j(H-1) as fractions of the velocity limit. a_jH and b_jH follow from rest at t = 0.
class Coding {
 public:
  Coding(const ExcitationLimits& limits, int harmonics, double period,
         const std::optional<Eigen::VectorXd>& offset)
      : limits_(limits), h_(harmonics), period_(period), fixed_offset_(offset) {}

  int n() const { return static_cast<int>(limits_.q_min.size()); }
  int perJoint() const { return (fixed_offset_ ? 0 : 1) + 2 * (h_ - 1); }
  int size() const { return n() * perJoint(); }

  FourierSeries decode(const double* x) const {
    FourierSeries d;
    d.period = period_;
    d.offset.resize(n());
    d.a.resize(n(), h_);
    d.b.resize(n(), h_);
    for (int j = 0; j < n(); ++j) {
      const double* u = x + j * perJoint();
      if (fixed_offset_) {
        d.offset[j] = (*fixed_offset_)[j];
      } else {
        d.offset[j] = middle(j) + half(j) * *u++;
      }
      double sum_a = 0.0, sum_kb = 0.0;
      for (int k = 0; k < h_ - 1; ++k) {
        d.a(j, k) = limits_.dq_max[j] * u[k];
        d.b(j, k) = limits_.dq_max[j] * u[h_ - 1 + k];
        sum_a += d.a(j, k);
        sum_kb += (k + 1) * d.b(j, k);
      }
      d.a(j, h_ - 1) = -sum_a;
      d.b(j, h_ - 1) = -sum_kb / h_;
    }
    return d;
  }

  std::vector<double> encode(const FourierSeries& d) const {
    std::vector<double> x(size());
    for (int j = 0; j < n(); ++j) {
      double* u = x.data() + j * perJoint();
      if (!fixed_offset_) *u++ = (d.offset[j] - middle(j)) / half(j);
      for (int k = 0; k < h_ - 1; ++k) {
        u[k] = d.a(j, k) / limits_.dq_max[j];
        u[h_ - 1 + k] = d.b(j, k) / limits_.dq_max[j];
      }
    }
    return x;
  }

  double middle(int j) const { return 0.5 * (limits_.q_min[j] + limits_.q_max[j]); }
  double half(int j) const { return 0.5 * (limits_.q_max[j] - limits_.q_min[j]); }
  bool offsetFixed() const { return fixed_offset_.has_value(); }

 private:
  const ExcitationLimits& limits_;
  int h_;
  double period_;
  std::optional<Eigen::VectorXd> fixed_offset_;
};

/// Peaks of q, dq, ddq of joint j on the grid rows.
struct JointPeaks {
  double q_low, q_high, dq, ddq;
};
JointPeaks peaksOf(const Eigen::MatrixXd& q, const Eigen::MatrixXd& dq, const Eigen::MatrixXd& ddq,
                   int j) {
  return {q.row(j).minCoeff(), q.row(j).maxCoeff(), dq.row(j).cwiseAbs().maxCoeff(),
          ddq.row(j).cwiseAbs().maxCoeff()};
}

/// Scales joint j's coefficients about its offset so that its excursion, speed and acceleration
/// use at most `fraction` of the limits (positions: of the room between the offset and each
/// limit). Returns false when the offset itself lies outside the limits.
bool fitJoints(FourierSeries& d, const Grid& g, const ExcitationLimits& limits, double fraction) {
  Eigen::MatrixXd q, dq, ddq;
  motionOnGrid(d, g, q, dq, ddq);
  for (int j = 0; j < d.numJoints(); ++j) {
    const JointPeaks p = peaksOf(q, dq, ddq, j);
    const double up = limits.q_max[j] - d.offset[j], down = d.offset[j] - limits.q_min[j];
    if (!(up > 0.0) || !(down > 0.0)) return false;
    double s = std::numeric_limits<double>::infinity();
    if (p.q_high > d.offset[j]) s = std::min(s, fraction * up / (p.q_high - d.offset[j]));
    if (p.q_low < d.offset[j]) s = std::min(s, fraction * down / (d.offset[j] - p.q_low));
    if (p.dq > 0.0) s = std::min(s, fraction * limits.dq_max[j] / p.dq);
    if (p.ddq > 0.0) s = std::min(s, fraction * limits.ddq_max[j] / p.ddq);
    if (std::isfinite(s) && s < 1.0) {
      d.a.row(j) *= s;
      d.b.row(j) *= s;
    }
  }
  return true;
}

/// The optimisation problem on the coarse grid: criterion and normalised constraints (<= 0).
class DesignProblem {
 public:
  DesignProblem(const Model& model, const BaseParameters& base, const ExciteRequest& request,
                const ExcitationLimits& limits, const Coding& coding, const Grid& grid)
      : model_(model),
        base_(base),
        request_(request),
        limits_(limits),
        coding_(coding),
        grid_(grid),
        theta_(model.standardParameters()),
        scale_(baseParameterScale(base.project(theta_))) {}

  int numConstraints() const {
    int per_joint = 4;
    if (limits_.tau_max.allFinite()) per_joint = 5;
    return per_joint * model_.numJoints() + (limits_.floor ? 1 : 0) +
           (limits_.base_radius > 0.0 ? 1 : 0);
  }

  /// Per-thread scratch.
  struct Workspace {
    explicit Workspace(const Model& model) : data(model) {}
    Data data;
    Eigen::MatrixXd q, dq, ddq, tau, w1, gram;
    Eigen::LLT<Eigen::MatrixXd> llt;
  };

  /// The criterion at x, and the constraints into c (numConstraints() entries).
  double evaluate(const double* x, double* c, Workspace& w) const {
    const FourierSeries d = coding_.decode(x);
    const int n = model_.numJoints(), m_count = grid_.points(), b = base_.numBase();
    motionOnGrid(d, grid_, w.q, w.dq, w.ddq);
    w.w1.resize(static_cast<Eigen::Index>(m_count) * n, b);
    w.tau.resize(n, m_count);
    double lowest = std::numeric_limits<double>::infinity(),
           nearest = std::numeric_limits<double>::infinity();
    for (int m = 0; m < m_count; ++m) {
      const Eigen::MatrixXd& Y =
          jointTorqueRegressor(model_, w.data, w.q.col(m), w.dq.col(m), w.ddq.col(m));
      w.tau.col(m).noalias() = Y * theta_;
      for (int j = 0; j < b; ++j) w.w1.block(m * n, j, n, 1) = Y.col(base_.independent[j]);
      if (request_.criterion == ExcitationCriterion::kGc) {  // M^-1 W1: the first-order GC rows
        w.llt.compute(crba(model_, w.data, w.q.col(m)));
        auto rows = w.w1.middleRows(static_cast<Eigen::Index>(m) * n, n);
        w.llt.solveInPlace(rows);
      }
      if (limits_.floor || limits_.base_radius > 0.0) {
        const auto& frames = forwardKinematics(model_, w.data, w.q.col(m));
        for (const auto& f : frames) lowest = std::min(lowest, f.translation.z());
        nearest = std::min(nearest, frames.back().translation.head<2>().norm());
      }
    }
    int i = 0;
    for (int j = 0; j < n; ++j) {
      const JointPeaks p = peaksOf(w.q, w.dq, w.ddq, j);
      const double half = coding_.half(j), room = (1.0 - kGridMargin) * half;
      c[i++] = (p.q_high - (limits_.q_max[j] - room)) / half;
      c[i++] = ((limits_.q_min[j] + room) - p.q_low) / half;
      c[i++] = p.dq / (kGridMargin * limits_.dq_max[j]) - 1.0;
      c[i++] = p.ddq / (kGridMargin * limits_.ddq_max[j]) - 1.0;
      if (limits_.tau_max.allFinite())
        c[i++] = w.tau.row(j).cwiseAbs().maxCoeff() /
                     (kGridMargin * limits_.torque_margin * limits_.tau_max[j]) -
                 1.0;
    }
    if (limits_.floor) c[i++] = *limits_.floor - lowest;  // [m]
    if (limits_.base_radius > 0.0) c[i++] = 1.0 - nearest / limits_.base_radius;

    w.gram.setZero(b, b);
    w.gram.selfadjointView<Eigen::Lower>().rankUpdate(w.w1.transpose());
    return criterion(w.gram.selfadjointView<Eigen::Lower>(), static_cast<double>(w.w1.rows()));
  }

 private:
  double criterion(const Eigen::MatrixXd& gram, double rows) const {
    if (!gram.allFinite()) return kInfeasibleObjective;
    switch (request_.criterion) {
      case ExcitationCriterion::kDOptimal: {
        const Eigen::LLT<Eigen::MatrixXd> llt(gram / rows);
        if (llt.info() != Eigen::Success) return kInfeasibleObjective;
        return -2.0 * llt.matrixLLT().diagonal().array().log().sum();
      }
      case ExcitationCriterion::kGc:
      case ExcitationCriterion::kConditionUnit: {
        const Eigen::VectorXd d = gram.diagonal().cwiseSqrt();
        if (!(d.minCoeff() > 0.0)) return kInfeasibleObjective;
        const Eigen::VectorXd inv = d.cwiseInverse();
        return logCondition(inv.asDiagonal() * gram * inv.asDiagonal());
      }
      case ExcitationCriterion::kCondition:
        return logCondition(gram);
      case ExcitationCriterion::kRelativeSd: {  // log RMS_j sqrt((G^-1)_jj) / s_j, up to a constant
        const Eigen::LLT<Eigen::MatrixXd> llt(gram / rows);
        if (llt.info() != Eigen::Success) return kInfeasibleObjective;
        // (G^-1)_jj = |L^-1 e_j|^2: the column norms of L^-1.
        const Eigen::MatrixXd l_inverse =
            llt.matrixL().solve(Eigen::MatrixXd::Identity(gram.rows(), gram.cols()));
        const double mean_square =
            (l_inverse.colwise().squaredNorm().transpose().array() / scale_.array().square())
                .mean();
        return std::isfinite(mean_square) ? 0.5 * std::log(mean_square) : kInfeasibleObjective;
      }
    }
    return kInfeasibleObjective;
  }

  /// log cond of W1 from its Gram matrix G: half the log of G's eigenvalue ratio.
  static double logCondition(const Eigen::MatrixXd& gram) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram, Eigen::EigenvaluesOnly);
    const Eigen::VectorXd& l = eigen.eigenvalues();
    if (eigen.info() != Eigen::Success || !(l[0] > 0.0)) return kInfeasibleObjective;
    return 0.5 * std::log(l[l.size() - 1] / l[0]);
  }

  const Model& model_;
  const BaseParameters& base_;
  const ExciteRequest& request_;
  const ExcitationLimits& limits_;
  const Coding& coding_;
  const Grid& grid_;
  Eigen::VectorXd theta_;
  Eigen::VectorXd scale_;  // of the base parameters' relative errors (relative-sd)
};

/// A start's random design: coefficients N(0, 1/k) (lower harmonics carry more), rest at t = 0,
/// the offset at mid-range (or fixed), scaled per joint to 80 % of the limits on the grid.
FourierSeries randomStart(const Coding& coding, const ExcitationLimits& limits, const Grid& grid,
                          int harmonics, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> x(coding.size(), 0.0);
  const int per = coding.perJoint(), skip = coding.offsetFixed() ? 0 : 1;
  for (int j = 0; j < coding.n(); ++j)
    for (int k = 0; k < 2 * (harmonics - 1); ++k)
      x[j * per + skip + k] = normal(rng) / (1 + k % (harmonics - 1));
  FourierSeries d = coding.decode(x.data());
  fitJoints(d, grid, limits, 0.8);
  return d;
}

/// The GC residuals' exact Jacobian with respect to the base parameters at the model's own
/// parameters: the motion's segments (its inverse-dynamics torques held between samples, RK4 at
/// its sample period), d(residual)/d(theta) restricted to the independent columns, which is
/// d(residual)/d(beta) since the dynamics depend on theta only through beta.
double gcCondition(const Model& model, const BaseParameters& base, const Trajectory& motion,
                   const ExciteRequest& request, int threads) {
  SegmentOptions options;
  options.horizon = request.gc_horizon;
  options.num_segments = request.gc_segments;
  const GcProblem problem = makeGcProblem(motion, options);
  return scaledConditionNumber(base.baseRegressor(gcJacobian(model, problem, threads)));
}

/// The first-order GC rows M(q)^-1 W1 of every sample, and their unit-column condition number.
double firstOrderGcCondition(const Model& model, const BaseParameters& base,
                             const Trajectory& motion) {
  const int n = model.numJoints(), b = base.numBase();
  Data data(model);
  Eigen::MatrixXd rows(static_cast<Eigen::Index>(motion.numSamples()) * n, b);
  Eigen::LLT<Eigen::MatrixXd> llt(n);
  for (int k = 0; k < motion.numSamples(); ++k) {
    const Eigen::MatrixXd& Y =
        jointTorqueRegressor(model, data, motion.q.col(k), motion.dq.col(k), motion.ddq.col(k));
    auto block = rows.middleRows(static_cast<Eigen::Index>(k) * n, n);
    for (int j = 0; j < b; ++j) block.col(j) = Y.col(base.independent[j]);
    llt.compute(crba(model, data, motion.q.col(k)));
    llt.solveInPlace(block);
  }
  return scaledConditionNumber(rows);
}

}  // namespace

const std::vector<std::string>& excitationCriterionNames() {
  static const std::vector<std::string> names = {"cond", "cond-unscaled", "d-optimal", "gc",
                                                 "relative-sd"};
  return names;
}

std::string excitationCriterionName(ExcitationCriterion criterion) {
  return excitationCriterionNames()[static_cast<int>(criterion)];
}

ExcitationCriterion parseExcitationCriterion(const std::string& name) {
  const auto& names = excitationCriterionNames();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<ExcitationCriterion>(i);
  throw InputError("unknown criterion '" + name +
                   "': expected cond, cond-unscaled, d-optimal, gc or relative-sd");
}

SinusoidalReference defaultSinusoid(const Model& model) {
  const int n = model.numJoints();
  SinusoidalReference r;
  r.q0 = defaultCentre(model);
  r.amplitude = Eigen::VectorXd::Constant(n, 0.5);
  r.frequency = defaultFrequencies(n);
  r.phase = Eigen::VectorXd::Zero(n);
  return r;
}

Trajectory sampleFourier(const FourierSeries& design, const Model& model, double rate) {
  if (design.numJoints() != model.numJoints())
    throw InputError("the design has " + std::to_string(design.numJoints()) + " joints, model '" +
                     model.name + "' has " + std::to_string(model.numJoints()));
  if (!(rate > 0.0) || !std::isfinite(rate)) throw InputError("the sample rate must be > 0");
  const double points = std::round(design.period * rate) + 1.0;
  requireMemory(points * model.numJoints() * 5 * sizeof(double), "the sampled design");
  return sampleOn(design, model,
                  Grid(design.period, design.harmonics(), static_cast<int>(points), true));
}

void ExciteRequest::check() const {
  const int n = robot.numJoints();
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw InputError(message);
  };
  // The ranges of the one option table (core/option_ranges.hpp), in the request's field names.
  checkOption("excite", "period", period, "`period`");
  checkOption("excite", "harmonics", harmonics, "`harmonics`");
  checkOption("excite", "starts", starts, "`starts`");
  checkOption("excite", "evaluations", evaluations, "`evaluations`");
  checkOption("excite", "grid-rate", grid_rate, "`grid_rate`");
  checkOption("excite", "check-rate", check_rate, "`check_rate`");
  checkOption("excite", "torque-noise", torque_noise, "`torque_noise`");
  checkOption("excite", "segments", gc_segments, "`gc_segments`");
  checkOption("excite", "threads", threads, "`threads`");
  structural.check();
  // max_seconds: +inf (no budget) or a budget-seconds > 0.
  require(!(max_seconds <= 0.0), "max_seconds must be > 0");
  if (std::isfinite(max_seconds))
    checkOption("excite", "budget-seconds", max_seconds, "`max_seconds`");
  require(gc_horizon > 0.0 && gc_horizon <= period &&
              std::abs(gc_horizon * check_rate - std::round(gc_horizon * check_rate)) <= 1e-6 &&
              std::round(gc_horizon * check_rate) >= 1.0,
          "the GC horizon must be a whole number of check-rate samples, within the period");
  require(limits.q_min.size() == n, "the limits are for another joint count");
  require(std::ceil(period * grid_rate) <= 1e6,
          "the optimiser's grid would have more than 1e6 points");
  requireMemory(period * check_rate * n * 7 * sizeof(double),
                "the design sampled at the check rate");
  if (offset) checkOffsets(robot, limits, *offset);
  checkOption("excite", "payload-proximal-share", payload_proximal_share,
              "`payload_proximal_share`");
  if (payload_link) {
    require(*payload_link >= 0 && *payload_link < n,
            "payload_link " + std::to_string(*payload_link) + " is not a link of the robot");
    require(period <= 20.0, "a payload motion lasts at most 20 s, not " + formatNumber(period));
  }
}

namespace {

/// The best feasible design one start found.
struct StartBest {
  std::vector<double> x;
  double objective = std::numeric_limits<double>::infinity();
  int evaluations = 0;
};

/// The multistart COBYLA: each start from its seeded random design, stopped by the flag or the
/// deadline (then `interrupted` or `timed_out` is set).
struct MultiStart {
  const ExciteRequest& request;
  const Coding& coding;
  const Grid& grid;
  const DesignProblem& problem;
  RunControl control;  // the request's, with the design's time budget as its deadline
  std::atomic<bool> timed_out{false}, interrupted{false};

  /// Start s on `w`: its best feasible design.
  StartBest run(int s, DesignProblem::Workspace& w) {
    StartBest mine;
    const int m = problem.numConstraints();
    const FourierSeries start =
        randomStart(coding, request.limits, grid, request.harmonics,
                    splitmix(request.seed ^ splitmix(static_cast<std::uint64_t>(s))));
    std::vector<double> x = coding.encode(start);
    // COBYLA asks for the objective and then the constraints at the same x: one evaluation
    // serves both.
    std::vector<double> last_x, last_c(m);
    double last_f = 0.0;
    // Returns false when the design must stop (the flag or the time budget).
    auto evaluate = [&](const double* at) {
      if (!last_x.empty() && std::equal(last_x.begin(), last_x.end(), at)) return true;
      if (control.stopped()) {
        if (control.interrupted())
          interrupted = true;
        else
          timed_out = true;
        return false;
      }
      last_x.assign(at, at + x.size());
      last_f = problem.evaluate(at, last_c.data(), w);
      ++mine.evaluations;
      const bool feasible =
          std::all_of(last_c.begin(), last_c.end(), [](double c) { return c <= 0.0; });
      if (feasible && last_f < mine.objective) {
        mine.objective = last_f;
        mine.x = last_x;
      }
      return true;
    };
    CobylaProblem cobyla;
    cobyla.dimension = static_cast<int>(x.size());
    cobyla.objective = [&](const double* at) -> std::optional<double> {
      if (!evaluate(at)) return std::nullopt;
      return last_f;
    };
    cobyla.inequalities = m;
    cobyla.inequality = [&](const double* at, double* c) {
      // At the x the objective was just given (COBYLA's order): the cached constraints. Should
      // the run have to stop there, every constraint reads violated.
      if (evaluate(at))
        std::copy(last_c.begin(), last_c.end(), c);
      else
        std::fill(c, c + m, std::numeric_limits<double>::infinity());
    };
    cobyla.initial_step = {0.05};
    cobyla.max_evaluations = request.evaluations;
    cobyla.xtol_rel = 1e-6;
    // A failure (e.g. a non-finite step) leaves the best feasible point so far standing.
    runCobyla(cobyla, x);
    return mine;
  }
};

/// Why no start met the limits: the constraints of start 0's initial design.
[[noreturn]] void throwNoFeasibleStart(const ExciteRequest& request, const Coding& coding,
                                       const Grid& grid, const std::string& termination) {
  const Model& model = request.robot;
  const FourierSeries start = randomStart(coding, request.limits, grid, request.harmonics,
                                          splitmix(request.seed ^ splitmix(0)));
  const LimitCheck check = checkLimits(model, sampleOn(start, model, grid), request.limits);
  std::string why = check.violations.empty() ? "" : ": " + check.violations.front();
  if (termination != "evaluations")
    throw Error("the design was stopped (" + termination + ") before any start met the limits" +
                why);
  throw Error("no start met the limits" + why +
              " (raise the limit, lower the torque margin's demand, or use `offset`)");
}

/// The check at check_rate: shrinks out.design's coefficients until no limit is crossed between
/// grid points (positions, speeds and accelerations scale with them; torques are re-checked).
/// Returns the checked motion.
Trajectory shrinkIntoLimits(const ExciteRequest& request, ExciteOutcome& out) {
  const Model& model = request.robot;
  Trajectory motion = sampleFourier(out.design, model, request.check_rate);
  out.check = checkLimits(model, motion, request.limits);
  for (int tries = 0; !out.check.violations.empty() && tries < 200; ++tries) {
    const FourierSeries before = out.design;
    fitJoints(out.design, Grid(request.period, request.harmonics, motion.numSamples(), true),
              request.limits, 1.0);
    if (out.design.a == before.a && out.design.b == before.b) {  // torque or workspace: shrink all
      out.design.a *= 0.98;
      out.design.b *= 0.98;
    }
    motion = sampleFourier(out.design, model, request.check_rate);
    out.check = checkLimits(model, motion, request.limits);
  }
  if (!out.check.violations.empty())
    throw Error("the best design still breaks a limit at " + formatNumber(request.check_rate) +
                " Hz after shrinking: " + out.check.violations.front());
  return motion;
}

/// The default sinusoid over one period, at `samples` points, with its inverse dynamics.
Trajectory sinusoidBaseline(const Model& model, double period, int samples) {
  const int n = model.numJoints();
  const SinusoidalReference sinusoid = defaultSinusoid(model);
  const Grid check_grid(period, 1, samples, true);
  Trajectory baseline;
  baseline.resize(n, samples);
  baseline.time = check_grid.time;
  Data data(model);
  Eigen::VectorXd q(n), dq(n), ddq(n);
  for (int k = 0; k < baseline.numSamples(); ++k) {
    evaluateReference(sinusoid, baseline.time[k], q, dq, ddq);
    baseline.q.col(k) = q;
    baseline.dq.col(k) = dq;
    baseline.ddq.col(k) = ddq;
    baseline.tau.col(k) = rnea(model, data, q, dq, ddq);
  }
  return baseline;
}

/// A payload motion: the joints before the wrist kept near the middle of their range (or their
/// fixed offset); the design is then made within those limits.
ExciteRequest proximalNarrowed(const ExciteRequest& request) {
  const int n = request.robot.numJoints();
  ExciteRequest narrowed = request;
  narrowed.payload_proximal_share = 1.0;
  ExcitationLimits& l = narrowed.limits;
  for (int j = 0; j < n - 3; ++j) {
    const double half = 0.5 * (l.q_max[j] - l.q_min[j]) * request.payload_proximal_share;
    const double centre =
        request.offset ? std::clamp((*request.offset)[j], l.q_min[j] + half, l.q_max[j] - half)
                       : 0.5 * (l.q_max[j] + l.q_min[j]);
    l.q_min[j] = centre - half;
    l.q_max[j] = centre + half;
  }
  l.notes.push_back("payload motion: joints 1 to " + std::to_string(n - 3) + " kept within " +
                    formatNumber(100.0 * request.payload_proximal_share, 3) +
                    " % of their range, so that the motion is mainly the wrist's");
  return narrowed;
}

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// The outcome's settings and the base parameters the design is scored on (the payload's 10, or
/// the whole robot's).
ExciteOutcome outcomeSettings(const ExciteRequest& request) {
  const Model& model = request.robot;
  ExciteOutcome out;
  out.criterion = request.criterion;
  out.limits = request.limits;
  out.torque_noise = request.torque_noise;
  out.check_rate = request.check_rate;
  out.grid_rate = request.grid_rate;
  out.seed = request.seed;
  out.payload_link = request.payload_link;
  if (request.payload_link) {
    const ParameterLayout layout = model.parameterLayout();
    std::vector<int> block;
    for (int k = 0; k < kLinkParameterCount; ++k)
      block.push_back(layout.linkIndex(*request.payload_link, k));
    out.base = blockBaseParameters(model, block, request.structural);
  } else {
    out.base = structuralBaseParameters(model, request.structural);
  }
  out.gc_segments = request.gc_segments;
  out.gc_horizon = request.gc_horizon;
  return out;
}

/// Scores the default sinusoid (they do not depend on the design) and returns the seconds left
/// for the search. Its exact GC Jacobian takes as long as the design's will after the search,
/// so a time budget (max_seconds) holds with the design's evaluation included.
double scoreBaseline(const ExciteRequest& request, int threads, Clock::time_point started,
                     ExciteOutcome& out) {
  const Model& model = request.robot;
  const Trajectory baseline = sinusoidBaseline(
      model, request.period, static_cast<int>(std::round(request.period * request.check_rate)) + 1);
  out.baseline = scoreMotion(model, out.base, baseline, request.torque_noise);
  out.baseline_check = checkLimits(model, baseline, request.limits);
  const auto gc_started = Clock::now();
  out.baseline_gc = gcCondition(model, out.base, baseline, request, threads);
  const double gc_seconds = secondsSince(gc_started);
  out.baseline_gc_first_order = firstOrderGcCondition(model, out.base, baseline);
  // What is left for the search: the budget less what has run and the design's evaluation (its
  // GC Jacobian and the limits' shrinking: twice the baseline's Jacobian), at least a tenth of it.
  if (!std::isfinite(request.max_seconds)) return request.max_seconds;
  return std::max(request.max_seconds - secondsSince(started) - 2.0 * gc_seconds,
                  0.1 * request.max_seconds);
}

/// Runs every start on the pool, reporting each as it finishes (the share done: of the starts or
/// of the budget, whichever is further).
std::vector<StartBest> runStarts(const ExciteRequest& request, MultiStart& multistart,
                                 ThreadPool& pool, Clock::time_point started) {
  std::vector<StartBest> best(request.starts);
  std::mutex progress_mutex;
  int finished = 0;
  std::vector<std::unique_ptr<DesignProblem::Workspace>> workspaces;
  for (int t = 0; t < pool.numThreads(); ++t)
    workspaces.push_back(std::make_unique<DesignProblem::Workspace>(request.robot));
  pool.parallelFor(request.starts, [&](int s, int thread) {
    best[s] = multistart.run(s, *workspaces[thread]);
    if (!request.control.progress) return;
    std::lock_guard<std::mutex> lock(progress_mutex);
    ++finished;
    const double elapsed = secondsSince(started);
    std::ostringstream line;
    line << "start " << finished << "/" << request.starts << ": "
         << (std::isfinite(best[s].objective) ? "criterion " + formatNumber(best[s].objective)
                                              : std::string("no design within the limits"))
         << " after " << best[s].evaluations << " evaluations; "
         << progressText(std::max(static_cast<double>(finished) / request.starts,
                                  elapsed / request.max_seconds),
                         elapsed);
    request.control.progress(line.str());
  });
  return best;
}

/// Tallies the starts and picks the best (none feasible: an error saying why).
void tallyStarts(const ExciteRequest& request, const std::vector<StartBest>& best,
                 const MultiStart& multistart, ExciteOutcome& out) {
  out.starts.resize(request.starts);
  for (int s = 0; s < request.starts; ++s) {
    out.starts[s].evaluations = best[s].evaluations;
    out.evaluations += best[s].evaluations;
    if (std::isfinite(best[s].objective)) {
      out.starts[s].objective = best[s].objective;
      if (out.best_start < 0 || best[s].objective < best[out.best_start].objective)
        out.best_start = s;
    }
  }
  out.termination = multistart.interrupted ? "interrupted"
                    : multistart.timed_out ? "seconds"
                                           : "evaluations";
  if (out.best_start < 0)
    throwNoFeasibleStart(request, multistart.coding, multistart.grid, out.termination);
}

}  // namespace

ExciteOutcome exciteRun(const ExciteRequest& request) {
  request.check();
  const int n = request.robot.numJoints();
  if (request.starts == 0) {
    ExciteRequest resolved = request;
    resolved.starts = request.payload_link ? kPayloadStarts : kDefaultStarts;
    return exciteRun(resolved);
  }
  if (request.payload_link && request.payload_proximal_share < 1.0 && n > 3)
    return exciteRun(proximalNarrowed(request));
  const Model& model = request.robot;
  const auto started = Clock::now();
  ExciteOutcome out = outcomeSettings(request);
  ThreadPool pool(request.threads == 0 ? 0 : std::min(request.threads, request.starts));
  const double search_seconds = scoreBaseline(request, pool.numThreads(), started, out);

  const int grid_points = static_cast<int>(std::ceil(request.period * request.grid_rate));
  const Coding coding(request.limits, request.harmonics, request.period, request.offset);
  const Grid grid(request.period, request.harmonics, grid_points, false);
  const DesignProblem problem(model, out.base, request, request.limits, coding, grid);
  MultiStart multistart{request, coding, grid, problem,
                        request.control.within(search_seconds, Clock::now())};
  const std::vector<StartBest> best = runStarts(request, multistart, pool, started);
  tallyStarts(request, best, multistart, out);

  out.design = coding.decode(best[out.best_start].x.data());
  const Trajectory motion = shrinkIntoLimits(request, out);
  const Eigen::MatrixXd& a0 = coding.decode(best[out.best_start].x.data()).a;
  out.shrink = a0.norm() > 0.0 ? out.design.a.norm() / a0.norm() : 1.0;
  out.score = scoreMotion(model, out.base, motion, request.torque_noise);
  // The exact GC Jacobian takes seconds: after Ctrl-C it is left out (NaN), so that the design is
  // written within a second of it.
  out.gc = multistart.interrupted
               ? std::numeric_limits<double>::quiet_NaN()
               : gcCondition(model, out.base, motion, request, pool.numThreads());
  out.gc_first_order = firstOrderGcCondition(model, out.base, motion);
  out.seconds = secondsSince(started);
  return out;
}

}  // namespace dynid
