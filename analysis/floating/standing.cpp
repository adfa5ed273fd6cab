#include "analysis/floating/standing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/QR>

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

/// The contacts' stacked Jacobian (base axes) at q.
Eigen::MatrixXd stacked(const FloatingModel& model, FloatingData& data,
                        const std::vector<Contact>& contacts, const Eigen::VectorXd& q) {
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

/// The contacts' pose error at q for the base at `base`, against their world poses `world`
/// (base axes; a frame contact's rotation first, as its Jacobian's rows).
Eigen::VectorXd poseError(const FloatingModel& model, FloatingData& data,
                          const std::vector<Contact>& contacts,
                          const std::vector<Pose<double>>& world, const BasePose& base,
                          const Eigen::VectorXd& q) {
  Eigen::VectorXd e(stacked(model, data, contacts, q).rows());
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
    const Eigen::MatrixXd Jq = stacked(model, data, contacts, q).rightCols(n);
    q += Jq.completeOrthogonalDecomposition().solve(e);
    if (!q.allFinite()) return false;
  }
  return poseError(model, data, contacts, world, base, q).lpNorm<Eigen::Infinity>() < 1e-12;
}

}  // namespace

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
  Eigen::VectorXd q = request.stance;
  for (int k = 0; k < N; ++k) {
    const double t = k / request.rate;
    const BasePose base = sway.at(t);
    if (!followContacts(model, data, request.contacts, world, base, q))
      throw InputError("the legs cannot follow the sway at t = " + formatNumber(t, 4) +
                       " s (a contact out of reach): lower `sway` or `turn`, or bend the `stance`");
    for (int j = 0; j < n; ++j) {
      const JointLimits& limits = model.limbs().limits[static_cast<std::size_t>(j)];
      if (q[j] < limits.lower || q[j] > limits.upper)
        throw InputError("the legs follow the sway past " + model.limbs().joint_names[j] +
                         "'s limits at t = " + formatNumber(t, 4) + " s (" + formatNumber(q[j], 4) +
                         " rad): lower `sway` or `turn`, or move the `stance`");
    }
    const Eigen::MatrixXd J = stacked(model, data, request.contacts, q);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> legs(J.rightCols(n));
    const Eigen::VectorXd dq = legs.solve(-J.leftCols<6>() * base.twist);
    Eigen::VectorXd nu(6 + n);
    nu << base.twist, dq;
    const double fastest = dq.lpNorm<Eigen::Infinity>();
    Eigen::VectorXd djnu = Eigen::VectorXd::Zero(J.rows());
    if (fastest > 0.0) {
      const double h = 1e-6 / fastest;
      djnu = (stacked(model, data, request.contacts, q + h * dq) -
              stacked(model, data, request.contacts, q - h * dq)) *
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
  }
  return out;
}

}  // namespace dynid
