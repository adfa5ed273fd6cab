#include "data/dh.hpp"

#include <cmath>
#include <numbers>

#include "core/errors.hpp"

namespace dynid {

namespace {

/// cos and sin of `angle`, exact (0, +-1) within 1e-12 rad of a multiple of pi/2 up to 1e9 quarter
/// turns; beyond that (a finite angle nobody means, which the fuzzer sent) std::cos and std::sin,
/// never an int conversion out of range.
std::pair<double, double> cosSin(double angle) {
  const double quarter = angle / (std::numbers::pi / 2.0);
  const double k = std::round(quarter);
  if (std::abs(k) < 1e9 && std::abs(quarter - k) * (std::numbers::pi / 2.0) < 1e-12) {
    const int m = ((static_cast<int>(k) % 4) + 4) % 4;
    constexpr double kCos[4] = {1.0, 0.0, -1.0, 0.0}, kSin[4] = {0.0, 1.0, 0.0, -1.0};
    return {kCos[m], kSin[m]};
  }
  return {std::cos(angle), std::sin(angle)};
}

Pose<double> rotationX(double angle) {
  Pose<double> p;
  p.rotation = dhRotationX(angle);
  return p;
}
Pose<double> rotationZ(double angle) {
  Pose<double> p;
  p.rotation = dhRotationZ(angle);
  return p;
}
Pose<double> translation(double x, double z) {
  Pose<double> p;
  p.translation = Eigen::Vector3d(x, 0.0, z);
  return p;
}

}  // namespace

const char* dhConventionName(DhConvention convention) {
  return convention == DhConvention::kStandard ? "standard" : "modified";
}

Eigen::Matrix3d dhRotationX(double angle) {
  const auto [c, s] = cosSin(angle);
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, c, -s, 0, s, c;
  return r;
}

Eigen::Matrix3d dhRotationZ(double angle) {
  const auto [c, s] = cosSin(angle);
  Eigen::Matrix3d r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}

RigidInertia<double> inertiaFromCom(double mass, const Eigen::Vector3d& com,
                                    const Eigen::Matrix3d& inertia_about_com) {
  RigidInertia<double> out;
  out.mass = mass;
  out.first_moment = mass * com;
  out.inertia = inertia_about_com +
                mass * (com.squaredNorm() * Eigen::Matrix3d::Identity() - com * com.transpose());
  return out;
}

Model modelFromDh(const DhModel& dh) {
  Model model;
  model.name = dh.name;
  model.setGravity(dh.gravity);
  model.setDriveTerms(dh.drive_terms);
  for (std::size_t i = 0; i < dh.rows.size(); ++i) {
    const DhRow& r = dh.rows[i];
    for (double x : {r.a, r.d, r.alpha, r.theta_offset})
      if (!std::isfinite(x))
        throw InputError("DH row " + std::to_string(i + 1) + " (joint '" + r.joint_name +
                         "'): a, d, alpha and theta_offset must be finite");
    const bool prismatic = r.type == JointType::kPrismatic;
    Pose<double> joint_placement, body_placement;
    if (dh.convention == DhConvention::kStandard) {
      // Rz(theta) Tz(d) Tx(a) Rx(alpha): the joint's motion first, then the link's constant part.
      if (prismatic)
        body_placement = rotationZ(r.theta_offset) * translation(0.0, r.d) * translation(r.a, 0.0) *
                         rotationX(r.alpha);
      else
        joint_placement = rotationZ(r.theta_offset),
        body_placement = translation(r.a, r.d) * rotationX(r.alpha);
    } else {
      // Rx(alpha) Tx(a) Rz(theta) Tz(d): the constant part first, then the joint's motion.
      joint_placement = rotationX(r.alpha) * translation(r.a, 0.0) *
                        (prismatic ? rotationZ(r.theta_offset) * translation(0.0, r.d)
                                   : translation(0.0, r.d) * rotationZ(r.theta_offset));
    }
    model.addBody(static_cast<int>(i) - 1, r.link_name, r.joint_name, r.type, joint_placement,
                  Eigen::Vector3d::UnitZ(), body_placement, r.inertia, r.limits, r.drive);
  }
  model.finalize();
  return model;
}

}  // namespace dynid
