#include "data/puma560.hpp"

#include <array>
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

#include "core/errors.hpp"
#include "core/parameters.hpp"

namespace dynid {

namespace {
constexpr double kPi = std::numbers::pi;

struct DhRow {
  double d, a, alpha;
};
// Standard DH: T(i-1 -> i) = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i).
constexpr std::array<DhRow, 6> kDh = {{{0.0, 0.0, kPi / 2},
                                       {0.0, 0.4318, 0.0},
                                       {0.15005, 0.0203, -kPi / 2},
                                       {0.4318, 0.0, kPi / 2},
                                       {0.0, 0.0, -kPi / 2},
                                       {0.0, 0.0, 0.0}}};
// Paper form per link: m [kg], centre of mass [m], principal inertia about it [kg m^2].
constexpr std::array<std::array<double, 7>, 6> kLinks = {{
    {0.0, 0.0, 0.0, 0.0, 0.0, 0.35, 0.0},
    {17.4, -0.3638, 0.006, 0.2275, 0.13, 0.524, 0.539},
    {4.8, -0.0203, -0.0141, 0.070, 0.066, 0.086, 0.0125},
    {0.82, 0.0, 0.019, 0.0, 1.8e-3, 1.3e-3, 1.8e-3},
    {0.34, 0.0, 0.0, 0.0, 0.3e-3, 0.4e-3, 0.3e-3},
    {0.09, 0.0, 0.0, 0.032, 0.15e-3, 0.15e-3, 0.04e-3},
}};
struct DriveRow {
  double jm, gear, viscous, coulomb_plus, coulomb_minus;
};
constexpr std::array<DriveRow, 6> kDrives = {{{200e-6, -62.6111, 1.48e-3, 0.395, -0.435},
                                              {200e-6, 107.815, 0.817e-3, 0.126, -0.071},
                                              {200e-6, -53.7063, 1.38e-3, 0.132, -0.105},
                                              {33e-6, 76.0364, 71.2e-6, 11.2e-3, -16.9e-3},
                                              {33e-6, 71.923, 82.6e-6, 9.26e-3, -14.5e-3},
                                              {33e-6, 76.686, 36.7e-6, 3.96e-3, -10.5e-3}}};
constexpr std::array<double, 6> kLimitsDeg = {160, 110, 135, 266, 100, 266};
}  // namespace

Model makePuma560(bool drives) {
  Model model;
  model.name = "puma560";
  model.setGravity(Eigen::Vector3d(0.0, 0.0, -9.81));
  if (drives) model.setDriveTerms(kPuma560DriveTerms);
  for (int i = 0; i < 6; ++i) {
    const std::string index = std::to_string(i + 1);
    // Joint i turns about z_{i-1}; link frame i sits Tz(d) Tx(a) Rx(alpha) further.
    Pose<double> body_placement;
    // Rx(alpha); the twists are quarter turns, whose cosine is exactly 0 (not cos(pi/2) = 6e-17).
    const double ca = kDh[i].alpha == 0.0 ? 1.0 : 0.0,
                 sa = kDh[i].alpha > 0 ? 1.0 : (kDh[i].alpha < 0 ? -1.0 : 0.0);
    body_placement.rotation << 1, 0, 0, 0, ca, -sa, 0, sa, ca;
    body_placement.translation = Eigen::Vector3d(kDh[i].a, 0.0, kDh[i].d);
    const Eigen::Matrix<double, 7, 1> paper(kLinks[i].data());
    const RigidInertia<double> inertia = fromStandardVector(paperToStandard(paper));
    JointLimits limits;
    limits.lower = -kLimitsDeg[i] * kPi / 180.0;
    limits.upper = kLimitsDeg[i] * kPi / 180.0;
    DriveParameters<double> drive;
    const DriveRow& r = kDrives[i];
    const double g = r.gear, abs_g = std::abs(r.gear);
    drive[DriveTerm::kRotorInertia] = r.jm * g * g;
    drive[DriveTerm::kViscous] = g * g * r.viscous;
    drive[DriveTerm::kCoulomb] = abs_g * (r.coulomb_plus - r.coulomb_minus) / 2.0;
    drive[DriveTerm::kCoulombAsymmetry] = abs_g * (r.coulomb_plus + r.coulomb_minus) / 2.0;
    model.addBody(i - 1, "link" + index, "joint" + index, JointType::kRevolute, Pose<double>(),
                  Eigen::Vector3d::UnitZ(), body_placement, inertia, limits, drive);
  }
  model.finalize();
  return model;
}

Model makePuma560Consistent(bool drives) {
  Model model = makePuma560(drives);
  model.name = "puma560-consistent";
  // Link 1: 1 kg at the origin (on joint 1's axis), isotropic 0.35 kg m^2 (its axis inertia).
  RigidInertia<double> link1;
  link1.mass = 1.0;
  link1.inertia = 0.35 * Eigen::Matrix3d::Identity();
  model.setLinkInertia(0, link1);
  // Link 3: the smallest principal inertia about the centre of mass to 0.0215 kg m^2.
  RigidInertia<double> link3 = model.inertias()[2];
  const Eigen::Vector3d c = link3.first_moment / link3.mass;
  const Eigen::Matrix3d shift =
      link3.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(link3.inertia - shift);
  Eigen::Vector3d principal = eigen.eigenvalues();  // ascending
  principal[0] = 0.0215;
  link3.inertia =
      eigen.eigenvectors() * principal.asDiagonal() * eigen.eigenvectors().transpose() + shift;
  model.setLinkInertia(2, link3);
  return model;
}

Eigen::VectorXd puma560Pose(const std::string& name) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
  if (name == "qz") return q;
  if (name == "qr") {
    q << 0, kPi / 2, -kPi / 2, 0, 0, 0;
  } else if (name == "qs") {
    q << 0, 0, -kPi / 2, 0, 0, 0;
  } else if (name == "qn") {
    q << 0, kPi / 4, kPi, 0, kPi / 4, 0;
  } else {
    throw InputError("unknown PUMA 560 pose '" + name + "' (expected qz, qr, qs or qn)");
  }
  return q;
}

}  // namespace dynid
