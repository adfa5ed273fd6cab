#include "search/floating/floating_gc.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include <Eigen/QR>

#include "core/errors.hpp"
#include "core/floating/floating_rnea.hpp"
#include "core/format.hpp"

namespace dynid {
namespace {

/// The rolled-out state: the base's orientation (w, x, y, z) and twist, q, dq; and its rate.
struct FloatingState {
  Eigen::Vector4d orientation;
  Vector6<double> twist;
  Eigen::VectorXd q, dq;
};

/// a + h b, each part.
FloatingState step(const FloatingState& a, double h, const FloatingState& b) {
  return {a.orientation + h * b.orientation, a.twist + h * b.twist, a.q + h * b.q, a.dq + h * b.dq};
}

/// The quaternion product a b, both (w, x, y, z).
Eigen::Vector4d times(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  const Eigen::Vector3d u = a.tail<3>(), v = b.tail<3>();
  Eigen::Vector4d out;
  out[0] = a[0] * b[0] - u.dot(v);
  out.tail<3>() = a[0] * v + b[0] * u + cross(u, v);
  return out;
}

/// The segments' starts: every non-overlapping segment of each run (runs split where a step
/// exceeds 1.5 periods), then at most `wanted` of them evenly spaced (0: all).
std::vector<int> segmentStarts(const Eigen::VectorXd& time, double period, int samples,
                               int wanted) {
  std::vector<int> all;
  const int n = static_cast<int>(time.size());
  int run = 0;
  for (int k = 1; k <= n; ++k) {
    if (k < n && time[k] - time[k - 1] <= 1.5 * period) continue;
    for (int s = run; s + samples < k; s += samples) all.push_back(s);  // a run is [run, k)
    run = k;
  }
  if (wanted == 0 || static_cast<int>(all.size()) <= wanted) return all;
  std::vector<int> picked;
  for (int i = 0; i < wanted; ++i)
    picked.push_back(all[static_cast<std::size_t>(i * static_cast<long>(all.size()) / wanted)]);
  return picked;
}

/// The forward dynamics along a recording: the state's rate with sample k's torques and wrenches.
class FloatingRollout {
 public:
  FloatingRollout(const FloatingModel& model, const FloatingGcData& data)
      : model_(model), data_(data), work_(model) {}

  FloatingState rate(const FloatingState& s, int k) {
    const int n = model_.numJoints();
    BaseMotion base;
    base.rotation = baseRotation(Eigen::Vector4d(s.orientation.normalized()));
    base.twist = s.twist;
    // The contacts' measured wrenches as a generalized force J^T lambda, lambda in base axes.
    Eigen::VectorXd external = Eigen::VectorXd::Zero(6 + n);
    for (std::size_t c = 0; c < data_.contacts.size(); ++c) {
      const Contact& contact = data_.contacts[c];
      if (flagged(c)) continue;  // held below
      const Eigen::Matrix3d R = contactPose(model_, work_, contact, s.q).rotation;
      Eigen::VectorXd lambda(contact.dimension());
      for (int r = 0; r < contact.dimension(); r += 3)
        lambda.segment<3>(r) = R * data_.wrenches[c].col(k).segment<3>(r);
      external.noalias() += contactJacobian(model_, work_, contact, s.q).transpose() * lambda;
    }
    const Eigen::VectorXd tau = data_.tau.col(k) + external.tail(n);
    Eigen::VectorXd a = floatingForwardDynamics(model_, work_, base, s.q, s.dq, tau,
                                                Vector6<double>(external.head<6>()));
    hold(s, k, a);
    Eigen::Vector4d omega = Eigen::Vector4d::Zero();
    omega.tail<3>() = s.twist.head<3>();
    return {0.5 * times(s.orientation, omega), a.head<6>(), s.dq, a.tail(n)};
  }

  bool flagged(std::size_t c) const { return !data_.flags.empty() && !data_.flags[c].empty(); }

  /// The contacts sample k flags as holding: their rows J and the rate J dnu must have (the
  /// contact still in the world); 0 rows when none holds.
  void holdingRows(const FloatingState& s, int k, Eigen::MatrixXd& J, Eigen::VectorXd& rate) {
    const int nv = model_.numVelocities();
    Eigen::VectorXd nu(nv);
    nu << s.twist, s.dq;
    // dJ nu by central differences of J along dq (J depends on q only), the step putting 1e-5
    // rad on the fastest joint: 1e-10 relative truncation, 1e-11 round-off.
    const double fastest = s.dq.lpNorm<Eigen::Infinity>();
    const double h = fastest > 0.0 ? 1e-5 / fastest : 0.0;
    J.resize(0, nv);
    rate.resize(0);
    for (std::size_t c = 0; c < data_.contacts.size(); ++c) {
      if (!flagged(c) || !data_.flags[c][static_cast<std::size_t>(k)]) continue;
      const Contact& contact = data_.contacts[c];
      const Eigen::MatrixXd Jc = contactJacobian(model_, work_, contact, s.q);
      Eigen::VectorXd djnu = Eigen::VectorXd::Zero(Jc.rows());
      if (h > 0.0)
        djnu = (contactJacobian(model_, work_, contact, s.q + h * s.dq) -
                contactJacobian(model_, work_, contact, s.q - h * s.dq)) *
               nu / (2.0 * h);
      const Eigen::VectorXd v = Jc * nu;
      const Eigen::Vector3d omega = s.twist.head<3>();
      const Eigen::Index at = J.rows();
      J.conservativeResize(at + Jc.rows(), nv);
      rate.conservativeResize(at + Jc.rows());
      J.bottomRows(Jc.rows()) = Jc;
      for (Eigen::Index r = 0; r < Jc.rows(); r += 3)
        rate.segment<3>(at + r) =
            -djnu.segment<3>(r) - cross(omega, Eigen::Vector3d(v.segment<3>(r)));
    }
  }

  /// Adds to the free acceleration `a` what the holding contacts' forces do (the header's rule),
  /// with M's factor floatingForwardDynamics left in the workspace.
  void hold(const FloatingState& s, int k, Eigen::VectorXd& a) {
    if (data_.flags.empty()) return;
    Eigen::MatrixXd J;
    Eigen::VectorXd rate;
    holdingRows(s, k, J, rate);
    if (J.rows() == 0) return;
    const Eigen::MatrixXd MinvJt = work_.llt.solve(J.transpose());
    const Eigen::MatrixXd A = J * MinvJt;
    const Eigen::VectorXd lambda = A.completeOrthogonalDecomposition().solve(rate - J * a);
    a.noalias() += MinvJt * lambda;
  }

  /// One RK4 step of length h with sample k's inputs; the orientation normalised after it.
  void rk4(FloatingState& s, int k, double h) {
    const FloatingState k1 = rate(s, k), k2 = rate(step(s, 0.5 * h, k1), k);
    const FloatingState k3 = rate(step(s, 0.5 * h, k2), k), k4 = rate(step(s, h, k3), k);
    s = step(s, h / 6.0,
             {k1.orientation + 2.0 * k2.orientation + 2.0 * k3.orientation + k4.orientation,
              k1.twist + 2.0 * k2.twist + 2.0 * k3.twist + k4.twist,
              k1.q + 2.0 * k2.q + 2.0 * k3.q + k4.q, k1.dq + 2.0 * k2.dq + 2.0 * k3.dq + k4.dq});
    s.orientation.normalize();
  }

  FloatingState recorded(int k) const {
    return {data_.orientation.col(k).normalized(), data_.twist.col(k), data_.q.col(k),
            data_.dq.col(k)};
  }

  /// The end-state difference at sample `end` of a segment rolled out from `start`
  /// (floatingGcResiduals' column), NaN where the rollout diverges.
  Eigen::VectorXd residual(int start, int end, int substeps) {
    const int n = model_.numJoints();
    Eigen::VectorXd out = Eigen::VectorXd::Constant(2 * n + 9, std::nan(""));
    FloatingState s = recorded(start);
    // A candidate far from physical (an unconstrained estimate's) can diverge: its state runs to
    // infinity, its quaternion to zero, or its mass matrix stops being positive definite (the
    // dynamics then throw). Such a segment counts as the cap, as a non-finite error does.
    try {
      for (int k = start; k < end; ++k) {
        const double h = (data_.time[k + 1] - data_.time[k]) / substeps;
        for (int i = 0; i < substeps; ++i) rk4(s, k, h);
        if (!s.orientation.allFinite() || !s.twist.allFinite() || !s.dq.allFinite()) return out;
      }
    } catch (const Error&) {
      return out;
    }
    const FloatingState r = recorded(end);
    // The rotation from the prediction to the record: conj(predicted) recorded, as its angle
    // times its axis (the shorter way round).
    Eigen::Vector4d conj = s.orientation;
    conj.tail<3>() = -conj.tail<3>();
    Eigen::Vector4d d = times(conj, r.orientation);
    if (d[0] < 0.0) d = -d;
    const double sine = d.tail<3>().norm();
    const double angle = 2.0 * std::atan2(sine, d[0]);
    const Eigen::Vector3d rotation =
        sine > 0.0 ? Eigen::Vector3d(angle / sine * d.tail<3>()) : Eigen::Vector3d::Zero();
    out << s.q - r.q, s.dq - r.dq, s.twist.head<3>() - r.twist.head<3>(),
        data_.linear_velocity ? Eigen::Vector3d(s.twist.tail<3>() - r.twist.tail<3>())
                              : Eigen::Vector3d::Zero(),
        rotation;
    return out;
  }

 private:
  const FloatingModel& model_;
  const FloatingGcData& data_;
  FloatingData work_;
};

void checkData(const FloatingModel& model, const FloatingGcData& data) {
  const Eigen::Index n = model.numJoints(), samples = data.time.size();
  const auto check = [&](bool ok, const char* field, const std::string& what) {
    if (!ok) throw InputError(std::string("`") + field + "`: " + what);
  };
  check(samples >= 2, "time", "two or more samples are needed, not " + std::to_string(samples));
  for (Eigen::Index k = 1; k < samples; ++k)
    check(data.time[k] > data.time[k - 1], "time",
          "sample " + std::to_string(k + 1) + " is not after the one before it");
  check(data.orientation.cols() == samples, "orientation", "one column a sample");
  check(data.twist.cols() == samples, "twist", "one column a sample");
  for (const auto& [m, field] : {std::pair{&data.q, "q"}, {&data.dq, "dq"}, {&data.tau, "tau"}})
    check(m->rows() == n && m->cols() == samples, field,
          std::to_string(n) + " x " + std::to_string(samples) + " (joints x samples), not " +
              std::to_string(m->rows()) + " x " + std::to_string(m->cols()));
  check(data.wrenches.size() == data.contacts.size(), "wrenches", "one matrix a contact");
  check(data.flags.empty() || data.flags.size() == data.contacts.size(), "flags",
        "none, or one list a contact");
  for (std::size_t c = 0; c < data.contacts.size(); ++c) {
    const Contact& contact = data.contacts[c];
    check(contact.body >= -1 && contact.body < n, "contacts",
          contact.name + "'s body is not the model's");
    if (!data.flags.empty() && !data.flags[c].empty()) {
      check(static_cast<Eigen::Index>(data.flags[c].size()) == samples, "flags",
            contact.name + "'s are one a sample (" + std::to_string(samples) + ")");
      continue;
    }
    check(data.wrenches[c].rows() == contact.dimension() && data.wrenches[c].cols() == samples,
          "wrenches",
          contact.name + "'s is " + std::to_string(contact.dimension()) + " x " +
              std::to_string(samples) + " (its components x samples), or give its flags");
  }
}

}  // namespace

void FloatingGcOptions::check() const {
  if (!(horizon > 0.0) || !std::isfinite(horizon))
    throw InputError("`horizon` is positive and finite");
  if (num_segments < 0) throw InputError("`num_segments` is 0 (every one) or positive");
  if (substeps < 1) throw InputError("`substeps` is 1 or more");
}

FloatingGcResult floatingGcSegments(const FloatingModel& model, const FloatingGcData& data,
                                    const FloatingGcOptions& options) {
  checkData(model, data);
  options.check();
  Eigen::VectorXd steps =
      data.time.tail(data.time.size() - 1) - data.time.head(data.time.size() - 1);
  std::sort(steps.data(), steps.data() + steps.size());
  const double period = steps[steps.size() / 2];
  // A recording's period is its median step, rarely a round number (a prepared log's 500.4 Hz):
  // the horizon is taken to the nearest whole number of periods, and said (FloatingGcResult).
  const double samples = std::round(options.horizon / period);
  if (samples < 1.0)
    throw InputError("`horizon`: " + formatNumber(options.horizon, 4) +
                     " s is shorter than half a sample period (" + formatNumber(period, 4) + " s)");
  if (samples * options.substeps > kMaxSegmentSteps)
    throw InputError("`substeps`: " + std::to_string(options.substeps) + " steps a period over " +
                     std::to_string(static_cast<long>(samples)) +
                     " periods is more than a segment may take (" +
                     std::to_string(static_cast<long>(kMaxSegmentSteps)) + ")");
  FloatingGcResult out;
  out.samples_per_segment = static_cast<int>(samples);
  out.horizon = samples * period;
  out.starts = segmentStarts(data.time, period, out.samples_per_segment, options.num_segments);
  if (out.starts.empty())
    throw InputError("`horizon`: no run of the data holds a segment of " +
                     formatNumber(options.horizon, 4) + " s");
  return out;
}

Eigen::MatrixXd floatingGcResiduals(const FloatingModel& candidate, const FloatingGcData& data,
                                    const FloatingGcResult& segments, int substeps,
                                    ThreadPool* pool) {
  const int count = static_cast<int>(segments.starts.size());
  Eigen::MatrixXd out(2 * candidate.numJoints() + 9, count);
  const auto one = [&](FloatingRollout& rollout, int i) {
    const int start = segments.starts[static_cast<std::size_t>(i)];
    out.col(i) = rollout.residual(start, start + segments.samples_per_segment, substeps);
  };
  if (pool == nullptr || pool->numThreads() == 1 || count < 2) {
    FloatingRollout rollout(candidate, data);
    for (int i = 0; i < count; ++i) one(rollout, i);
    return out;
  }
  std::vector<std::unique_ptr<FloatingRollout>> rollouts;
  for (int t = 0; t < pool->numThreads(); ++t)
    rollouts.push_back(std::make_unique<FloatingRollout>(candidate, data));
  pool->parallelFor(count, [&](int i, int thread) { one(*rollouts[thread], i); });
  return out;
}

double floatingSegmentError(const Eigen::VectorXd& residual) {
  const double error = residual.squaredNorm();
  return std::isfinite(error) ? std::min(error, kMaxSegmentError) : kMaxSegmentError;
}

FloatingGcResult floatingGcError(const FloatingModel& candidate, const FloatingGcData& data,
                                 const FloatingGcOptions& options) {
  FloatingGcResult out = floatingGcSegments(candidate, data, options);
  const Eigen::MatrixXd residuals = floatingGcResiduals(candidate, data, out, options.substeps);
  out.segment_errors.resize(residuals.cols());
  for (Eigen::Index i = 0; i < residuals.cols(); ++i)
    out.segment_errors[i] = floatingSegmentError(residuals.col(i));
  out.error = out.segment_errors.sum();
  return out;
}

}  // namespace dynid
