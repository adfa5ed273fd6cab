#include "core/simulate.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <optional>
#include <random>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/aba.hpp"
#include "core/crba.hpp"
#include "core/errors.hpp"
#include "core/friction.hpp"
#include "core/integrators.hpp"
#include "core/kinematics.hpp"
#include "core/memory.hpp"
#include "core/rnea.hpp"

namespace dynid {

namespace {
void requirePositiveFinite(double x, const char* name) {
  if (!(std::isfinite(x) && x > 0.0))
    throw InputError(std::string("simulation ") + name + " must be positive and finite (got " +
                     std::to_string(x) + ")");
}
void requireNonNegativeFinite(double x, const char* name) {
  if (!(std::isfinite(x) && x >= 0.0))
    throw InputError(std::string("simulation ") + name + " must be >= 0 and finite");
}
/// The fastest rate [1/s] of a damping (D = diag(d)) or stiffness (K = diag(k); then its
/// square) on the mass matrix M: the largest lambda of D x = lambda M x, which is real and >= 0
/// (similar to D^1/2 M^-1 D^1/2). `joint` receives the joint whose diagonal entry carries most of
/// that mode (the largest d_j x_j^2).
double fastestRate(const Eigen::MatrixXd& M, const Eigen::VectorXd& d, int& joint) {
  const Eigen::VectorXd root = d.cwiseMax(0.0).cwiseSqrt();
  const Eigen::MatrixXd S = root.asDiagonal() * M.llt().solve(Eigen::MatrixXd(root.asDiagonal()));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (S + S.transpose()));
  Eigen::Index top = 0;
  const double rate = std::max(eigen.eigenvalues().maxCoeff(&top), 0.0);
  // S's eigenvector y = D^1/2 x: joint j's share of the mode's dissipation is y_j^2.
  eigen.eigenvectors().col(top).cwiseAbs2().maxCoeff(&top);
  joint = static_cast<int>(top);
  return rate;
}

/// Why a simulation diverged, from the dynamics at the last finite configuration q ("" when no
/// cause is found): the model's viscous friction, integrated at `step`, decays faster than the
/// integrator is stable for (RK4: |lambda step| <= 2.785 on the negative real axis; semi-implicit
/// Euler: 2), or the controller's damping or stiffness, applied with its torque held over the
/// control period T, is beyond what such a loop is stable for (lambda T < 2, omega T < 2).
std::string divergenceCause(const Model& truth, const TrackingController& controller,
                            const SimulationOptions& options, const Eigen::VectorXd& q) {
  const int n = truth.numJoints();
  Data data(truth);
  const Eigen::MatrixXd M = crba(truth, data, q);
  if (!M.allFinite() || M.llt().info() != Eigen::Success) return "";
  std::ostringstream out;
  out.precision(3);
  const bool rk4 = options.integrator == IntegratorType::kRk4;
  const double limit = rk4 ? 2.785 : 2.0;
  int joint = 0;
  if (truth.driveTerms().has(DriveTerm::kViscous)) {
    Eigen::VectorXd fv(n);
    for (int i = 0; i < n; ++i) fv[i] = truth.drives()[i][DriveTerm::kViscous];
    const double rate = fastestRate(M, fv, joint);
    if (rate * options.step > limit) {
      const double period = 1.0 / options.record_rate;
      // The longest step that divides the recording period into 2^a 5^b steps (a short decimal
      // when the period is one) and keeps 10 % from the limit.
      const double needed = std::ceil(period * rate / (0.9 * limit));
      double substeps = 1e18;
      for (double twos = 1.0; twos < 2.0 * needed; twos *= 2.0)
        for (double m = twos; m < 5.0 * needed; m *= 5.0)
          if (m >= needed) substeps = std::min(substeps, m);
      const double step = period / substeps;
      const std::string j = std::to_string(joint + 1);
      out << ": the integration step " << options.step
          << " s is too long for the viscous friction: its fastest mode, mostly joint " << j
          << " (Fv" << j << " = " << fv[joint] << " N m s), decays in " << 1.0 / rate << " s, and "
          << (rk4 ? "RK4" : "semi-implicit Euler") << " is stable only for steps up to " << limit
          << " times that; a step of " << std::setprecision(12) << step << std::setprecision(3)
          << " s keeps it stable";
      if (!truth.driveTerms().inertial() && truth.drives()[joint][DriveTerm::kRotorInertia] > 0.0)
        out << ". The robot's rotor inertias (Ia" << j << " = "
            << truth.drives()[joint][DriveTerm::kRotorInertia]
            << " kg m^2) are not among its drive terms, so the friction of the drives acts on the "
               "links' inertia alone";
      return out.str();
    }
  }
  const double period = 1.0 / options.record_rate;
  const TrackingGains& gains = controller.gains();
  // Damping (rate lambda of kd) and stiffness (frequency omega of kp) against 2 / period.
  for (const bool stiffness : {false, true}) {
    const Eigen::VectorXd& g = stiffness ? gains.kp : gains.kd;
    const double rate = stiffness ? std::sqrt(fastestRate(M, g, joint)) : fastestRate(M, g, joint);
    if (!(rate * period > 2.0)) continue;  // NaN (infinite gains) included: no cause named
    out << ": the controller's " << (stiffness ? "stiffness" : "damping")
        << " is too high for its period " << period
        << " s (the torque is held over it): its fastest mode, mostly joint " << joint + 1 << " ("
        << (stiffness ? "kp = " : "kd = ") << g[joint] << (stiffness ? " N m/rad" : " N m s/rad")
        << (stiffness ? "), oscillates at " : "), has a rate of ") << rate
        << (stiffness ? " rad/s" : "/s")
        << ", and such a loop is stable only below 2/period; lower gains or a higher control "
           "(recording) rate keep it stable";
    return out.str();
  }
  return "";
}

void checkDisturbances(const Model& truth, const std::vector<Disturbance>& disturbances) {
  const int n = truth.numJoints();
  for (std::size_t k = 0; k < disturbances.size(); ++k) {
    const Disturbance& d = disturbances[k];
    const std::string which = "disturbance " + std::to_string(k + 1) + ": ";
    if (!(std::isfinite(d.start) && d.start >= 0.0 && std::isfinite(d.duration) &&
          d.duration > 0.0))
      throw InputError(which + "its start must be >= 0 and its duration > 0, both finite");
    if ((d.joint >= 0) == (d.link >= 0)) throw InputError(which + "give either a joint or a link");
    if (d.joint >= n || d.link >= n)
      throw InputError(which + "the robot '" + truth.name + "' has " + std::to_string(n) +
                       (d.joint >= 0 ? " joints" : " links"));
    if (!std::isfinite(d.torque) || !d.force.allFinite() || !d.moment.allFinite())
      throw InputError(which + "its torque, force and moment must be finite");
  }
}

/// The disturbances' joint torques at time t and state q.
void externalTorque(const Model& truth, Data& data, const std::vector<Disturbance>& disturbances,
                    double t, const Eigen::VectorXd& q, Eigen::VectorXd& out) {
  out.setZero();
  for (const Disturbance& d : disturbances) {
    if (t < d.start || t >= d.start + d.duration) continue;
    if (d.joint >= 0)
      out[d.joint] += d.torque;
    else
      out += wrenchJointTorques(truth, data, q, d.link, d.force, d.moment);
  }
}

/// Stick-slip friction between integration steps (SimulationOptions::stiction). A joint with a
/// static band (its friction needs sign(dq)) that is within its velocity window of zero at a
/// step's start, or crossed zero in the last step, stops and sticks when the friction holding it,
/// given the torques and the other joints' motion, lies in its band; otherwise it keeps its
/// velocity, and one at exactly zero slips toward the torque's side with the band's edge as its
/// friction until its velocity leaves zero. Which joints stick is decided once per step (the torque
/// is held over it) by releasing the joint furthest outside its band until every held one is in.
class StickSlip {
 public:
  explicit StickSlip(const Model& truth) : n_(truth.numJoints()), lo_(n_), hi_(n_), edge_(n_) {
    for (int j = 0; j < n_; ++j) {
      const auto band = staticFrictionBand(truth, j);
      lo_[j] = band.first, hi_[j] = band.second;
      if (band.second > band.first) banded_.push_back(j);
    }
    stuck_.assign(static_cast<std::size_t>(n_), 0);
    zero_.assign(static_cast<std::size_t>(n_), 0);
  }
  bool any() const { return !banded_.empty(); }

  /// The velocity window within which a joint counts as stopping (Karnopp's): what half its static
  /// band takes from its velocity in one step of length h, with the mass matrix at q. A joint that
  /// approaches zero velocity smoothly would otherwise never reach it exactly.
  void setWindow(const Model& m, Data& data, const Eigen::VectorXd& q, double h) {
    const Eigen::MatrixXd& M = crba(m, data, q);
    window_.setZero(n_);
    for (int j : banded_) window_[j] = h * 0.5 * (hi_[j] - lo_[j]) / M(j, j);
  }

  /// Decides the step from (q, dq) under `tau`: the banded joints within their window (and those
  /// in `also`) stop at zero velocity, and those the band cannot hold are released, in turn, the
  /// furthest outside its band first; a released joint keeps the velocity it had. True when a
  /// joint is stuck or slips from exactly zero velocity (the step then needs constrainedStep).
  bool decide(const Model& m, Data& data, const Eigen::VectorXd& q, Eigen::VectorXd& dq,
              const Eigen::VectorXd& tau, const std::vector<int>& also = {}) {
    bool candidates = false;
    saved_ = dq;
    for (int j = 0; j < n_; ++j) stuck_[j] = zero_[j] = 0;
    const auto stop = [&](int j) { stuck_[j] = zero_[j] = 1, dq[j] = 0.0, candidates = true; };
    for (int j : banded_)
      if (std::abs(dq[j]) <= window_[j]) stop(j);
    for (int j : also) stop(j);
    if (!candidates) return false;
    for (;;) {
      acceleration(m, data, q, dq, tau);
      int worst = -1;
      double most = 0.0;
      for (int j : banded_) {
        if (!stuck_[j]) continue;
        const double f = held_[j], outside = std::max(f - hi_[j], lo_[j] - f) / (hi_[j] - lo_[j]);
        if (outside > most) most = outside, worst = j;
      }
      if (worst < 0) break;
      stuck_[worst] = 0;
      edge_[worst] = held_[worst] > hi_[worst] ? hi_[worst] : lo_[worst];
    }
    bool constrained = false;
    for (int j : banded_) {
      if (zero_[j] && !stuck_[j] && saved_[j] != 0.0) zero_[j] = 0, dq[j] = saved_[j];
      constrained = constrained || zero_[j];
    }
    return constrained;
  }

  /// ddq under the decision: zero on the stuck joints, M's free block solved for the rest, with
  /// the edge friction of a slipping joint while its velocity is exactly zero; held_ receives
  /// the friction each stuck joint needs.
  const Eigen::VectorXd& acceleration(const Model& m, Data& data, const Eigen::VectorXd& q,
                                      const Eigen::VectorXd& dq, const Eigen::VectorXd& tau) {
    zero_ddq_.setZero(n_);
    bias_ = tau - rnea(m, data, q, dq, zero_ddq_);
    for (int j = 0; j < n_; ++j)
      if (zero_[j] && !stuck_[j] && dq[j] == 0.0) bias_[j] -= edge_[j];
    const Eigen::MatrixXd& M = crba(m, data, q);
    free_.clear();
    for (int j = 0; j < n_; ++j)
      if (!stuck_[j]) free_.push_back(j);
    const auto f = static_cast<Eigen::Index>(free_.size());
    block_.resize(f, f);
    rhs_.resize(f);
    for (Eigen::Index a = 0; a < f; ++a) {
      rhs_[a] = bias_[free_[a]];
      for (Eigen::Index b = 0; b < f; ++b) block_(a, b) = M(free_[a], free_[b]);
    }
    ddq_.setZero(n_);
    if (f > 0) {
      ldlt_.compute(block_);  // allocates only when the set of free joints changes size
      x_ = ldlt_.solve(rhs_);
      for (Eigen::Index a = 0; a < f; ++a) ddq_[free_[a]] = x_[a];
    }
    held_ = bias_;
    held_.noalias() -= M * ddq_;
    return ddq_;
  }

  /// One step of `type` under the decision (the stuck joints' q and dq stay as they are).
  void constrainedStep(IntegratorType type, const Model& m, Data& data, Eigen::VectorXd& q,
                       Eigen::VectorXd& dq, const Eigen::VectorXd& tau, double h) {
    if (type == IntegratorType::kSemiImplicitEuler) {
      dq += h * acceleration(m, data, q, dq, tau);
      q += h * dq;
      return;
    }
    // Classical RK4 on (q, dq) with this acceleration; the stages in members (no allocation once
    // sized). Stage i's state: q0 + c_i h v_{i-1}, dq0 + c_i h a_{i-1}.
    q0_ = q, dq0_ = dq;
    const double c[4] = {0.0, 0.5, 0.5, 1.0}, w[4] = {1.0, 2.0, 2.0, 1.0};
    q.setZero(), dq.setZero();  // the weighted sums of the stages' velocities and accelerations
    for (int i = 0; i < 4; ++i) {
      if (i == 0) {
        stage_q_ = q0_, stage_dq_ = dq0_;
      } else {
        stage_q_ = q0_ + (c[i] * h) * stage_dq_;  // the previous stage's velocity
        stage_dq_ = dq0_ + (c[i] * h) * stage_a_;
      }
      q += w[i] * stage_dq_;
      stage_a_ = acceleration(m, data, stage_q_, stage_dq_, tau);
      dq += w[i] * stage_a_;
    }
    q = q0_ + (h / 6.0) * q;
    dq = dq0_ + (h / 6.0) * dq;
  }

  /// After a step from velocities `before`: a banded joint whose velocity changed sign (or reached
  /// zero) is stopped at zero when its band holds it there under `tau`; else it goes on as
  /// integrated (a reversal the torque drives through).
  void settle(const Model& m, Data& data, const Eigen::VectorXd& q, const Eigen::VectorXd& before,
              Eigen::VectorXd& dq, const Eigen::VectorXd& tau) {
    crossed_.clear();
    for (int j : banded_)
      if (before[j] != 0.0 && (dq[j] == 0.0 || (dq[j] > 0.0) != (before[j] > 0.0)))
        crossed_.push_back(j);
    if (!crossed_.empty()) decide(m, data, q, dq, tau, crossed_);
  }

 private:
  int n_;
  Eigen::VectorXd lo_, hi_, edge_, window_, held_, bias_, ddq_, zero_ddq_, rhs_, saved_, x_;
  Eigen::VectorXd q0_, dq0_, stage_q_, stage_dq_, stage_a_;
  Eigen::MatrixXd block_;
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
  std::vector<int> banded_, free_, crossed_;
  std::vector<char> stuck_, zero_;
};
}  // namespace

Eigen::VectorXd wrenchJointTorques(const Model& model, Data& data, const Eigen::VectorXd& q,
                                   int link, const Eigen::Vector3d& force,
                                   const Eigen::Vector3d& moment) {
  const int n = model.numJoints();
  if (link < 0 || link >= n)
    throw InputError("link " + std::to_string(link) + " is out of range (the robot has " +
                     std::to_string(n) + ")");
  forwardKinematics(model, data, q);
  // The wrench about joint frame `link`'s origin, in its coordinates: n = R^T (M + (p - o) x F).
  const Pose<double>& joint = data.oMj[link];
  const Eigen::Vector3d arm = data.oMi[link].translation - joint.translation;
  for (int i = 0; i < n; ++i) data.f[i].setZero();
  data.f[link].head<3>() = joint.rotation.transpose() * (moment + cross(arm, force));
  data.f[link].tail<3>() = joint.rotation.transpose() * force;
  // tau_k = S_k^T f_k, f_parent += pXi* f_i, up the chain.
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(n);
  for (int i = link; i >= 0; --i) {
    tau[i] = projectOnJoint(model, i, data.f[i]);
    const int parent = model.parents()[i];
    if (parent >= 0) data.f[parent] += data.liMi[i].actForce(data.f[i]);
  }
  return tau;
}

namespace {
/// A run's size from its options: integration steps per recorded sample, and samples. Throws
/// InputError for the settings simulate() refuses (its contract).
struct RunSize {
  long substeps = 0, samples = 0;
};
RunSize runSize(const Model& truth, const TrackingController& controller,
                const SimulationOptions& options, const std::vector<Disturbance>& disturbances) {
  requirePositiveFinite(options.duration, "duration");
  requirePositiveFinite(options.step, "step");
  requirePositiveFinite(options.record_rate, "record rate");
  requireNonNegativeFinite(options.noise_q, "q noise");
  requireNonNegativeFinite(options.noise_dq, "dq noise");
  requireNonNegativeFinite(options.noise_tau, "tau noise");
  checkDisturbances(truth, disturbances);
  const int n = truth.numJoints();
  if (controller.numJoints() != n)
    throw InputError("controller has " + std::to_string(controller.numJoints()) +
                     " joints, model '" + truth.name + "' has " + std::to_string(n));
  const double period = 1.0 / options.record_rate;
  const double ratio = period / options.step;
  RunSize size;
  size.substeps = std::lround(ratio);
  if (size.substeps < 1 || std::abs(ratio - static_cast<double>(size.substeps)) > 1e-9 * ratio)
    throw InputError("the recording period 1/rate = " + std::to_string(period) +
                     " s is not a whole multiple of the integration step " +
                     std::to_string(options.step) + " s");
  size.samples = std::lround(std::floor(options.duration * options.record_rate + 1e-9)) + 1;
  if (size.samples > 100'000'000) throw InputError("simulation would record more than 1e8 samples");
  if (static_cast<double>(size.samples - 1) * static_cast<double>(size.substeps) > 1e9)
    throw InputError("simulation would take more than 1e9 integration steps (duration / step)");
  return size;
}
}  // namespace

Trajectory simulate(const Model& truth, TrackingController& controller,
                    const SimulationOptions& options, const std::vector<Disturbance>& disturbances,
                    Eigen::MatrixXd* applied) {
  const auto [substeps, samples] = runSize(truth, controller, options, disturbances);
  const int n = truth.numJoints();
  const double period = 1.0 / options.record_rate;
  Trajectory out;
  requireMemory(static_cast<double>(samples) * (1 + 4 * n) * sizeof(double),
                "a simulation of " + std::to_string(samples) + " samples");
  out.resize(n, static_cast<int>(samples));
  // The simulated physics: with stiction, the truth's friction law without a measurement's rest
  // velocities (a copy only then).
  std::optional<Model> cleared;
  if (options.stiction && !truth.rest_velocities.empty()) {
    cleared = truth;
    cleared->rest_velocities.clear();
  }
  const Model& physics = cleared ? *cleared : truth;
  Data data(physics);
  StickSlip stick(physics);
  const bool sticks = options.stiction && stick.any();
  Eigen::VectorXd q, dq, ddq_ref, before;
  controller.desired(0.0, q, dq, ddq_ref);
  if (sticks) stick.setWindow(physics, data, q, options.step);
  Eigen::VectorXd tau(n), external = Eigen::VectorXd::Zero(n), pushed(n);
  if (applied) applied->setZero(n, samples);
  for (long k = 0; k < samples; ++k) {
    // Sample k: t = k / rate; record the state, the controller torque and the true acceleration.
    const double t = static_cast<double>(k) * period;
    if (!q.allFinite() || !dq.allFinite()) {
      std::ostringstream msg;
      msg << "simulation of '" << truth.name << "' diverged at t = " << t << " s";
      if (k > 0) msg << divergenceCause(physics, controller, options, out.q.col(k - 1));
      throw NumericalError(msg.str());
    }
    controller.compute(t, q, dq, tau);
    if (!disturbances.empty()) externalTorque(physics, data, disturbances, t, q, external);
    pushed = tau + external;
    // A joint that stops here is recorded stopped (its velocity within the window, set to zero).
    bool held = sticks && stick.decide(physics, data, q, dq, pushed);
    out.time[k] = t;
    out.q.col(k) = q;
    out.dq.col(k) = dq;
    out.tau.col(k) = tau;
    if (applied) applied->col(k) = external;
    out.ddq.col(k) =
        held ? stick.acceleration(physics, data, q, dq, pushed) : aba(physics, data, q, dq, pushed);
    if (k + 1 == samples) break;
    // Hold tau over the recording period; the disturbances act at every step's start.
    for (long s = 0; s < substeps; ++s) {
      if (!disturbances.empty()) {
        externalTorque(physics, data, disturbances, t + static_cast<double>(s) * options.step, q,
                       external);
        pushed = tau + external;
      }
      if (!sticks) {
        integratorStep(options.integrator, physics, data, q, dq, pushed, options.step);
        continue;
      }
      if (s > 0) held = stick.decide(physics, data, q, dq, pushed);
      before = dq;
      if (held)
        stick.constrainedStep(options.integrator, physics, data, q, dq, pushed, options.step);
      else
        integratorStep(options.integrator, physics, data, q, dq, pushed, options.step);
      stick.settle(physics, data, q, before, dq, pushed);
    }
  }
  // Measurement noise on the recorded signals only.
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto add_noise = [&](Eigen::MatrixXd& m, double sigma) {
    if (sigma == 0.0) return;
    for (Eigen::Index k = 0; k < m.cols(); ++k)
      for (Eigen::Index i = 0; i < m.rows(); ++i) m(i, k) += sigma * normal(rng);
  };
  add_noise(out.q, options.noise_q);
  add_noise(out.dq, options.noise_dq);
  add_noise(out.tau, options.noise_tau);
  return out;
}

}  // namespace dynid
