#include "analysis/floating/standing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/QR>

#include "analysis/floating/identifiability.hpp"
#include "analysis/floating/simulate.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {
namespace {

/// The base's motion at time t: orientation R (base to world), origin p (world), the twist
/// (omega, v) in base axes and its derivative (dynid's convention: dv = R^T p'' - omega x v).
struct BasePose {
  Eigen::Matrix3d R;
  Eigen::Vector3d p;
  Vector6<double> twist, acceleration;
};

/// A designed sway's pose at t: the six coordinates' Fourier series, R = Rz(yaw) Ry(pitch)
/// Rx(roll) built factor by factor, R_k = R_(k-1) Q_k with Q_k a turn by theta_k about axis e_k:
/// the body rate w_k = Q_k^T w_(k-1) + theta_k' e_k and its derivative
/// Q_k^T w_(k-1)' - theta_k' e_k x Q_k^T w_(k-1) + theta_k'' e_k, exact.
BasePose designedPose(const FourierSeries& design, double t) {
  Eigen::VectorXd c, dc, ddc;
  evaluateReference(design, t, c, dc, ddc);
  BasePose out;
  out.R.setIdentity();
  Eigen::Vector3d omega = Eigen::Vector3d::Zero(), domega = Eigen::Vector3d::Zero();
  for (const int k : {5, 4, 3}) {  // yaw about z, pitch about y, roll about x
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(k - 3);
    const Eigen::Matrix3d Q = axisAngle(axis, c[k]);
    const Eigen::Vector3d carried = Q.transpose() * omega;
    domega = Q.transpose() * domega - dc[k] * axis.cross(carried) + ddc[k] * axis;
    omega = carried + dc[k] * axis;
    out.R = out.R * Q;
  }
  out.p = c.head<3>();
  const Eigen::Vector3d v = out.R.transpose() * dc.head<3>();
  out.twist << omega, v;
  out.acceleration << domega, out.R.transpose() * ddc.head<3>() - omega.cross(v);
  return out;
}

class Sway {
 public:
  explicit Sway(const StandingMotionRequest& r) : r_(r) {
    std::mt19937_64 rng(r.seed);
    std::uniform_real_distribution<double> phase(0.0, 2.0 * std::numbers::pi);
    std::normal_distribution<double> normal;
    for (double& f : phases_) f = phase(rng);
    axis_ = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  }

  BasePose at(double t) const {
    if (r_.base_design) return designedPose(*r_.base_design, t);
    const double w = 2.0 * std::numbers::pi / r_.period;
    Eigen::Vector3d p, dp, ddp;
    for (int i = 0; i < 3; ++i) {  // axis i at (i + 1) times the base frequency
      const double wi = (i + 1) * w, s = std::sin(wi * t + phases_[i]);
      const double c = std::cos(wi * t + phases_[i]);
      p[i] = r_.sway * (s - std::sin(phases_[i]));  // at rest at t = 0: p(0) = 0
      dp[i] = r_.sway * wi * c;
      ddp[i] = -r_.sway * wi * wi * s;
    }
    const double w2 = 2.0 * w, a = w2 * t + phases_[3];
    const double angle = r_.turn * (std::sin(a) - std::sin(phases_[3]));
    const double rate = r_.turn * w2 * std::cos(a), accel = -r_.turn * w2 * w2 * std::sin(a);
    BasePose out;
    out.R = axisAngle(axis_, angle);
    out.p = p;
    const Eigen::Vector3d omega = rate * axis_, v = out.R.transpose() * dp;
    out.twist << omega, v;
    out.acceleration << accel * axis_, out.R.transpose() * ddp - omega.cross(v);
    return out;
  }

 private:
  const StandingMotionRequest& r_;
  double phases_[4] = {};
  Eigen::Vector3d axis_;
};

/// The contacts' pose error at q for the base at `base`, against their world poses `world`
/// (base axes; a frame contact's rotation first, as its Jacobian's rows).
Eigen::VectorXd poseError(const FloatingModel& model, FloatingData& data,
                          const std::vector<Contact>& contacts,
                          const std::vector<Pose<double>>& world, const BasePose& base,
                          const Eigen::VectorXd& q) {
  Eigen::VectorXd e(stackedContactJacobian(model, data, contacts, q).rows());
  int row = 0;
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const Pose<double> now = contactPose(model, data, contacts[c], q);
    const Eigen::Vector3d target = base.R.transpose() * (world[c].translation - base.p);
    if (contacts[c].kind == Contact::Kind::kFrame) {
      const Eigen::AngleAxisd turn(base.R.transpose() * world[c].rotation *
                                   now.rotation.transpose());
      e.segment<3>(row) = turn.angle() * turn.axis();
      row += 3;
    }
    e.segment<3>(row) = target - now.translation;
    row += 3;
  }
  return e;
}

/// q at `base` by Newton's method from `q` (the sample before): the joints' columns of the
/// contacts' Jacobian, minimum-norm steps. False when it does not reach 1e-12.
bool followContacts(const FloatingModel& model, FloatingData& data,
                    const std::vector<Contact>& contacts, const std::vector<Pose<double>>& world,
                    const BasePose& base, Eigen::VectorXd& q) {
  const int n = model.numJoints();
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Eigen::VectorXd e = poseError(model, data, contacts, world, base, q);
    if (e.lpNorm<Eigen::Infinity>() < 1e-12) return true;
    const Eigen::MatrixXd Jq = stackedContactJacobian(model, data, contacts, q).rightCols(n);
    q += Jq.completeOrthogonalDecomposition().solve(e);
    if (!q.allFinite()) return false;
  }
  return poseError(model, data, contacts, world, base, q).lpNorm<Eigen::Infinity>() < 1e-12;
}

}  // namespace

StandingMotionRequest standingDesignRequest(const FloatingModel& model,
                                            const StandingDesignRecord& design, double rate,
                                            int samples) {
  const double period_samples = design.base.period * rate;
  if (!(rate > 0.0 && std::isfinite(rate)) ||
      (samples == 0 && period_samples > kMaxFloatingSamples))
    throw InputError("`rate` is positive and finite, at most " +
                     std::to_string(kMaxFloatingSamples) + " samples over the design's period (" +
                     formatNumber(design.base.period) + " s), not " + formatNumber(rate) + " Hz");
  StandingMotionRequest request;
  request.contacts = contactsOf(model, design.contacts);
  request.stance = design.stance;
  request.base_design = design.base;
  request.joint_design = design.joints;
  request.rate = rate;
  request.samples = samples > 0 ? samples : static_cast<int>(std::lround(period_samples));
  return request;
}

std::vector<char> heldJoints(const FloatingModel& model, const std::vector<Contact>& contacts) {
  std::vector<char> held(static_cast<std::size_t>(model.numJoints()), 0);
  for (const Contact& c : contacts)
    for (int b = c.body; b >= 0; b = model.limbs().parents()[static_cast<std::size_t>(b)])
      held[static_cast<std::size_t>(b)] = 1;
  return held;
}

Eigen::MatrixXd stackedContactJacobian(const FloatingModel& model, FloatingData& data,
                                       const std::vector<Contact>& contacts,
                                       const Eigen::VectorXd& q) {
  int rows = 0;
  for (const Contact& c : contacts) rows += c.dimension();
  Eigen::MatrixXd J(rows, model.numVelocities());
  rows = 0;
  for (const Contact& c : contacts) {
    J.middleRows(rows, c.dimension()) = contactJacobian(model, data, c, q);
    rows += c.dimension();
  }
  return J;
}

void StandingMotionRequest::check() const {
  const auto need = [](bool ok, const char* what) {
    if (!ok) throw InputError(what);
  };
  need(!contacts.empty(), "`contacts`: a standing robot holds on at least one");
  need(stance.allFinite(), "`stance` is finite");
  need(sway >= 0.0 && std::isfinite(sway), "`sway` is 0 or more and finite [m]");
  need(turn >= 0.0 && std::isfinite(turn), "`turn` is 0 or more and finite [rad]");
  need(period > 0.0 && std::isfinite(period), "`period` is positive and finite [s]");
  need(rate > 0.0 && std::isfinite(rate), "`rate` is positive and finite [Hz]");
  need(samples >= 2 && samples <= kMaxFloatingSamples, "`samples` is 2 to 1000000");
  if (!base_design) return;
  const FourierSeries& d = *base_design;
  need(d.offset.size() == 6 && d.a.rows() == 6 && d.b.rows() == 6 && d.a.cols() == d.b.cols() &&
           d.a.cols() >= 1,
       "`base_design` has six rows (x, y, z, roll, pitch, yaw) of as many harmonics");
  need(d.period > 0.0 && std::isfinite(d.period), "`base_design`'s period is positive and finite");
  need(d.offset.allFinite() && d.a.allFinite() && d.b.allFinite(),
       "`base_design`'s coefficients are finite");
}

std::shared_ptr<FloatingDataset> standingMotion(const FloatingModel& model,
                                                const StandingMotionRequest& request) {
  request.check();
  const int n = model.numJoints(), N = request.samples;
  if (request.stance.size() != n)
    throw InputError("`stance` has " + std::to_string(request.stance.size()) +
                     " joints, the model " + std::to_string(n));
  FloatingData data(model);
  std::vector<Pose<double>> world;  // at rest: the base at the origin, upright
  for (const Contact& c : request.contacts)
    world.push_back(contactPose(model, data, c, request.stance));
  auto out = std::make_shared<FloatingDataset>();
  out->joints = model.limbs().joint_names;
  out->time.resize(N);
  out->orientation.resize(4, N);
  out->twist.resize(6, N), out->acceleration.resize(6, N);
  out->q.resize(n, N), out->dq.resize(n, N), out->ddq.resize(n, N);
  out->tau.resize(0, N);
  for (const Contact& c : request.contacts)
    out->flags.push_back({c.name, std::vector<char>(static_cast<std::size_t>(N), 1)});
  const Sway sway(request);
  const std::string lower =
      request.base_design ? "a smaller sway (`base_design`)" : "lower `sway` or `turn`";
  if (request.joint_design && request.joint_design->numJoints() != n)
    throw InputError("`joint_design` has " + std::to_string(request.joint_design->numJoints()) +
                     " rows, the model " + std::to_string(n) + " joints");
  const std::vector<char> held = heldJoints(model, request.contacts);
  Eigen::VectorXd q = request.stance, free_q, free_dq, free_ddq;  // the free joints' motion
  for (int k = 0; k < N; ++k) {
    const double t = k / request.rate;
    const BasePose base = sway.at(t);
    if (request.joint_design) {
      evaluateReference(*request.joint_design, t, free_q, free_dq, free_ddq);
      for (int j = 0; j < n; ++j)
        if (!held[static_cast<std::size_t>(j)]) q[j] = free_q[j];  // Newton leaves them there
    }
    if (!followContacts(model, data, request.contacts, world, base, q))
      throw InputError("the legs cannot follow the sway at t = " + formatNumber(t, 4) +
                       " s (a contact out of reach): " + lower + ", or bend the `stance`");
    for (int j = 0; j < n && request.check_limits; ++j) {
      const JointLimits& limits = model.limbs().limits[static_cast<std::size_t>(j)];
      if (q[j] < limits.lower || q[j] > limits.upper)
        throw InputError(
            (held[static_cast<std::size_t>(j)] ? "the legs follow the sway past "
                                               : "`joint_design` moves the joints "
                                                 "past ") +
            model.limbs().joint_names[j] + "'s limits at t = " + formatNumber(t, 4) + " s (" +
            formatNumber(q[j], 4) + " rad): " +
            (held[static_cast<std::size_t>(j)] ? lower : std::string("a smaller `joint_design`")) +
            ", or move the `stance`");
    }
    const Eigen::MatrixXd J = stackedContactJacobian(model, data, request.contacts, q);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> legs(J.rightCols(n));
    const Eigen::VectorXd dq = legs.solve(-J.leftCols<6>() * base.twist);
    Eigen::VectorXd nu(6 + n);
    nu << base.twist, dq;
    const double fastest = dq.lpNorm<Eigen::Infinity>();
    Eigen::VectorXd djnu = Eigen::VectorXd::Zero(J.rows());
    if (fastest > 0.0) {
      const double h = 1e-6 / fastest;
      djnu = (stackedContactJacobian(model, data, request.contacts, q + h * dq) -
              stackedContactJacobian(model, data, request.contacts, q - h * dq)) *
             nu / (2.0 * h);
    }
    out->time[k] = t;
    const Eigen::Quaterniond quaternion(base.R);
    out->orientation.col(k) << quaternion.w(), quaternion.x(), quaternion.y(), quaternion.z();
    out->twist.col(k) = base.twist;
    out->acceleration.col(k) = base.acceleration;
    out->q.col(k) = q;
    out->dq.col(k) = dq;
    out->ddq.col(k) = legs.solve(-J.leftCols<6>() * base.acceleration - djnu);
    for (int j = 0; j < n && request.joint_design; ++j)
      if (!held[static_cast<std::size_t>(j)])  // no contact's Jacobian has their columns
        out->dq(j, k) = free_dq[j], out->ddq(j, k) = free_ddq[j];
  }
  return out;
}

}  // namespace dynid
