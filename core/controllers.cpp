#include "core/controllers.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/checks.hpp"
#include "core/crba.hpp"
#include "core/rnea.hpp"

namespace dynid {

Eigen::VectorXd defaultFrequencies(int n) {
  Eigen::VectorXd f(n);
  for (int i = 0; i < n; ++i) f[i] = 0.15 + 0.07 * i;
  return f;
}

Eigen::VectorXd defaultCentre(const Model& model) {
  Eigen::VectorXd q0(model.numJoints());
  for (int i = 0; i < model.numJoints(); ++i) {
    const JointLimits& l = model.limits[i];
    q0[i] = std::isfinite(l.lower) && std::isfinite(l.upper) ? 0.5 * (l.lower + l.upper) : 0.0;
  }
  return q0;
}

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;

void evaluate(const SinusoidalReference& r, double t, Eigen::VectorXd& q, Eigen::VectorXd& dq,
              Eigen::VectorXd& ddq) {
  const Eigen::Index n = r.q0.size();
  if (r.amplitude.size() != n || r.frequency.size() != n || r.phase.size() != n)
    throw InputError("sinusoidal reference: q0, amplitude, frequency and phase need " +
                     std::to_string(n) + " entries each");
  q.resize(n), dq.resize(n), ddq.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double w = kTwoPi * r.frequency[i];
    const double s = std::sin(w * t + r.phase[i]), c = std::cos(w * t + r.phase[i]);
    q[i] = r.q0[i] + r.amplitude[i] * s;
    dq[i] = r.amplitude[i] * w * c;
    ddq[i] = -r.amplitude[i] * w * w * s;
  }
}

void evaluate(const FourierSeries& r, double t, Eigen::VectorXd& q, Eigen::VectorXd& dq,
              Eigen::VectorXd& ddq) {
  const Eigen::Index n = r.offset.size();
  if (r.a.rows() != n || r.b.rows() != n || r.a.cols() != r.b.cols())
    throw InputError("Fourier series: a and b need " + std::to_string(n) +
                     " rows and the same number of harmonics");
  if (!(r.period > 0.0)) throw InputError("Fourier series: the period must be > 0");
  q = r.offset;
  dq.setZero(n);
  ddq.setZero(n);
  // 2 pi times the base frequency 1 / period, in that order: a tracking reference's rounding.
  const double w = kTwoPi * (1.0 / r.period);
  for (Eigen::Index k = 1; k <= r.a.cols(); ++k) {
    const double wk = w * static_cast<double>(k);
    const double s = std::sin(wk * t), c = std::cos(wk * t);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double a = r.a(i, k - 1), b = r.b(i, k - 1);
      q[i] += a / wk * s - b / wk * c;
      dq[i] += a * c + b * s;
      ddq[i] += -a * wk * s + b * wk * c;
    }
  }
}
}  // namespace

void evaluateReference(const Reference& reference, double t, Eigen::VectorXd& q,
                       Eigen::VectorXd& dq, Eigen::VectorXd& ddq) {
  std::visit([&](const auto& r) { evaluate(r, t, q, dq, ddq); }, reference);
}

std::string Pauses::problem() const {
  if (!std::isfinite(ramp) || ramp <= 0.0) return "ramp must be > 0 [s]";
  if (!std::isfinite(move) || move <= 2.0 * ramp) return "move must exceed twice the ramp [s]";
  if (!std::isfinite(hold) || hold < 0.0) return "hold must be >= 0 [s]";
  return {};
}

void Pauses::check() const {
  if (const std::string why = problem(); !why.empty()) throw InputError("`pauses`: " + why);
}

void Pauses::warp(double t, double& tau, double& speed, double& rate) const {
  // One cycle: a ramp up, full speed, a ramp down, the hold. A ramp's s = sin^2(a u), a = pi/(2
  // ramp), integrates to u/2 - sin(2 a u)/(4 a); the cycle advances the reference by move - ramp.
  const double cycle = move + hold, a = std::numbers::pi / (2.0 * ramp);
  const double cycles = std::floor(t / cycle), u = t - cycles * cycle;
  const auto rise = [&](double x) { return 0.5 * x - std::sin(2.0 * a * x) / (4.0 * a); };
  tau = cycles * (move - ramp);
  if (u < ramp) {
    tau += rise(u);
    speed = std::pow(std::sin(a * u), 2);
    rate = a * std::sin(2.0 * a * u);
  } else if (u < move - ramp) {
    tau += 0.5 * ramp + (u - ramp);
    speed = 1.0, rate = 0.0;
  } else if (u < move) {
    const double x = move - u;  // the ramp down mirrors the ramp up
    tau += (move - ramp) - rise(x);
    speed = std::pow(std::sin(a * x), 2);
    rate = -a * std::sin(2.0 * a * x);
  } else {
    tau += move - ramp;
    speed = rate = 0.0;
  }
}

TrackingGains defaultGains(const Model& model, const Eigen::VectorXd& q, double bandwidth_hz,
                           double damping) {
  Data data(model);
  const Eigen::VectorXd diag = crba(model, data, q).diagonal();
  const double w = kTwoPi * bandwidth_hz;
  return {diag * (w * w), diag * (2.0 * damping * w)};
}

double closedLoopFrequency(const Model& model, const Eigen::VectorXd& q,
                           const Eigen::VectorXd& kp) {
  Data data(model);
  const Eigen::MatrixXd M = crba(model, data, q);
  // M^-1 Kp is similar to Kp^1/2 M^-1 Kp^1/2 (symmetric): its eigenvalues are real and >= 0.
  const Eigen::VectorXd root = kp.cwiseMax(0.0).cwiseSqrt();
  const Eigen::MatrixXd S = root.asDiagonal() * M.llt().solve(Eigen::MatrixXd(root.asDiagonal()));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (S + S.transpose()),
                                                             Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(eigen.eigenvalues().maxCoeff(), 0.0)) / kTwoPi;
}

TrackingGains effectiveInertiaGains(const Model& model, const Eigen::VectorXd& q,
                                    double bandwidth_hz, double damping) {
  Data data(model);
  const Eigen::MatrixXd M = crba(model, data, q);
  const Eigen::VectorXd effective =
      M.llt().solve(Eigen::MatrixXd::Identity(M.rows(), M.cols())).diagonal().cwiseInverse();
  const double w = kTwoPi * bandwidth_hz;
  return {effective * (w * w), effective * (2.0 * damping * w)};
}

TrackingController::TrackingController(const Model& model, Reference reference, TrackingGains gains,
                                       Eigen::VectorXd torque_limit)
    : model_(model),
      data_(model_),
      reference_(std::move(reference)),
      gains_(std::move(gains)),
      torque_limit_(std::move(torque_limit)) {
  checkSize(model_, gains_.kp, "kp");
  checkSize(model_, gains_.kd, "kd");
  checkSize(model_, torque_limit_, "torque limit");
  if ((torque_limit_.array() <= 0.0).any() || torque_limit_.hasNaN())
    throw InputError("torque limits must be positive");
  evaluateReference(reference_, 0.0, q_des_, dq_des_, ddq_des_);
  checkSize(model_, q_des_, "controller reference");
  zero_ = Eigen::VectorXd::Zero(model_.numJoints());
}

void TrackingController::setPauses(const Pauses& pauses) {
  pauses.check();
  pauses_ = pauses;
}

void TrackingController::desired(double t, Eigen::VectorXd& q, Eigen::VectorXd& dq,
                                 Eigen::VectorXd& ddq) const {
  if (!pauses_) {
    evaluateReference(reference_, t, q, dq, ddq);
    return;
  }
  // q(tau(t)): dq = q' s, ddq = q'' s^2 + q' s'.
  double tau = 0.0, speed = 0.0, rate = 0.0;
  pauses_->warp(t, tau, speed, rate);
  evaluateReference(reference_, tau, q, dq, ddq);
  ddq = ddq * (speed * speed) + dq * rate;
  dq *= speed;
}

void TrackingController::compute(double t, const Eigen::Ref<const Eigen::VectorXd>& q,
                                 const Eigen::Ref<const Eigen::VectorXd>& dq,
                                 Eigen::Ref<Eigen::VectorXd> tau) {
  desired(t, q_des_, dq_des_, ddq_des_);
  // tau = Kp e + Kd de + g_ctrl(q), saturated.
  const Eigen::VectorXd& gravity = rnea(model_, data_, q, zero_, zero_);
  tau = gains_.kp.cwiseProduct(q_des_ - q) + gains_.kd.cwiseProduct(dq_des_ - dq) + gravity;
  tau = tau.cwiseMax(-torque_limit_).cwiseMin(torque_limit_);
}

}  // namespace dynid
