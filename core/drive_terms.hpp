// The drive terms: per-joint torques added to the rigid-body dynamics, one table row each.
// Every term is linear in its one parameter theta_k: tau_k = theta_k phi_k(dq, ddq), so it has a
// regressor column phi_k and identification stays a linear least-squares problem. A row gives the
// term's key (flags, JSON "drive_terms"), its parameter name (m3, Fv3: "Fv"), unit, law, sign
// constraint (the physically consistent estimator's positivity), how a perturbation draws it and
// its URDF attribute; driveBasis gives phi_k beside it. Everything else (names, parsing, the
// regressor's drive columns, friction, perturbation, JSON/URDF mapping, CLI help) is built from
// these two. docs/ARCHITECTURE.md, "A new drive term".
#pragma once

#include <array>
#include <cmath>
#include <string_view>

namespace dynid {

/// One drive term; its value is its row in kDriveTermTable and its column order within a joint.
enum class DriveTerm {
  kRotorInertia = 0,
  kViscous,
  kCoulomb,
  kOffset,
  kCoulombAsymmetry,
  kStribeck,
};

/// The fixed Stribeck velocity vs of the Stribeck term [rad/s or m/s]: the speed below which the
/// breakaway friction exceeds the Coulomb level (typical harmonic drives and gearboxes: 0.01-0.1
/// rad/s; Armstrong-Helouvry's survey). Fixed so that the term stays linear in Fs.
inline constexpr double kStribeckVelocity = 0.05;

struct DriveTermInfo {
  /// Whether a seeded perturbation (core/perturb.hpp) draws the term even when the model does not
  /// carry it (the five original terms, so seeded results stay the same) or only when it does.
  enum class Draw { kAlways, kWhenEnabled };
  DriveTerm term;
  std::string_view key;   // "fv"
  std::string_view name;  // "Fv": parameter names Fv1, Fv2, ...
  std::string_view unit;
  std::string_view law;          // "Fv dq"
  std::string_view description;  // "viscous friction"
  bool non_negative;             // physically >= 0 (pc estimator positivity)
  Draw draw;
  bool inertial;                   // phi = ddq: adds to the mass matrix's diagonal (CRBA, ABA)
  std::string_view urdf_dynamics;  // the <dynamics> attribute carrying it, or empty
  /// phi depends on sign(dq): at rest (|dq| within the rest velocity, core/model.hpp) the term
  /// is static friction, any value between its two one-sided limits at dq = 0 that the other
  /// torques demand, so its point value there is zero and its column is not fitted there.
  bool signed_by_velocity;
  std::string_view mjcf_joint;  // the MJCF <joint> attribute carrying it (MuJoCo), or empty
};

inline constexpr std::array<DriveTermInfo, 6> kDriveTermTable = {{
    {DriveTerm::kRotorInertia, "ia", "Ia", "kg m^2", "Ia ddq", "rotor inertia", true,
     DriveTermInfo::Draw::kAlways, true, "", false, "armature"},
    {DriveTerm::kViscous, "fv", "Fv", "N m s/rad", "Fv dq", "viscous friction", true,
     DriveTermInfo::Draw::kAlways, false, "damping", false, "damping"},
    {DriveTerm::kCoulomb, "fc", "Fc", "N m", "Fc sign(dq)", "Coulomb friction", true,
     DriveTermInfo::Draw::kAlways, false, "friction", true, "frictionloss"},
    {DriveTerm::kOffset, "fo", "Fo", "N m", "Fo", "constant offset (sensor or current bias)", false,
     DriveTermInfo::Draw::kWhenEnabled, false, "", false, ""},
    {DriveTerm::kCoulombAsymmetry, "fa", "Fa", "N m", "Fa |sign(dq)|", "Coulomb asymmetry", false,
     DriveTermInfo::Draw::kAlways, false, "", true, ""},
    {DriveTerm::kStribeck, "fs", "Fs", "N m", "Fs sign(dq) exp(-(dq/vs)^2), vs = 0.05 rad/s",
     "Stribeck (breakaway) friction", true, DriveTermInfo::Draw::kWhenEnabled, false, "", true, ""},
}};

inline constexpr int kDriveTermCount = static_cast<int>(kDriveTermTable.size());

/// sign(x) in {-1, 0, 1}; for dual numbers (ceres::Jet) the derivative part is zero.
template <typename Scalar>
inline Scalar signum(const Scalar& x) {
  if (x > Scalar(0)) return Scalar(1);
  if (x < Scalar(0)) return Scalar(-1);
  return Scalar(0);
}

/// sign(x) outside the rest band [-rest, rest] and 0 inside it (rest >= 0; rest = 0 is signum):
/// the sign a velocity measured within its noise of zero cannot be given.
template <typename Scalar>
inline Scalar signOutside(const Scalar& x, double rest) {
  if (x > Scalar(rest)) return Scalar(1);
  if (x < Scalar(-rest)) return Scalar(-1);
  return Scalar(0);
}

/// phi_k(dq, ddq): term k's regressor entry at joint velocity dq and acceleration ddq; its torque
/// is theta_k phi_k. One case per table row. `rest` >= 0 is the joint's rest velocity: the
/// signed_by_velocity terms are 0 for |dq| <= rest (static friction's point value; 0 keeps
/// sign(0) = 0 exactly as before).
template <typename Scalar>
inline Scalar driveBasis(int k, const Scalar& dq, const Scalar& ddq, double rest = 0.0) {
  using std::exp;
  switch (static_cast<DriveTerm>(k)) {
    case DriveTerm::kRotorInertia:
      return ddq;
    case DriveTerm::kViscous:
      return dq;
    case DriveTerm::kCoulomb:
      return signOutside(dq, rest);
    case DriveTerm::kOffset:
      return Scalar(1);
    case DriveTerm::kCoulombAsymmetry: {
      const Scalar s = signOutside(dq, rest);
      return s * s;
    }
    case DriveTerm::kStribeck: {
      const Scalar r = dq / Scalar(kStribeckVelocity);
      return signOutside(dq, rest) * exp(-(r * r));
    }
  }
  return Scalar(0);
}

namespace drive_terms_detail {
template <std::string_view DriveTermInfo::*Field>
constexpr std::array<std::string_view, kDriveTermCount> column() {
  std::array<std::string_view, kDriveTermCount> out{};
  for (int k = 0; k < kDriveTermCount; ++k) out[k] = kDriveTermTable[k].*Field;
  return out;
}
constexpr bool rowsInOrder() {
  for (int k = 0; k < kDriveTermCount; ++k)
    if (static_cast<int>(kDriveTermTable[k].term) != k) return false;
  return true;
}
}  // namespace drive_terms_detail
static_assert(drive_terms_detail::rowsInOrder(), "kDriveTermTable rows follow the enum");

/// The parameter names ("Ia", "Fv", ...) and keys ("ia", "fv", ...) in column order.
inline constexpr std::array<std::string_view, kDriveTermCount> kDriveParameterNames =
    drive_terms_detail::column<&DriveTermInfo::name>();
inline constexpr std::array<std::string_view, kDriveTermCount> kDriveTermKeys =
    drive_terms_detail::column<&DriveTermInfo::key>();

}  // namespace dynid
