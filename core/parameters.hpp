// The one place that defines dynid's parameter conventions. Every report, JSON file, test and
// estimator uses these names and this order.
//
// Standard parameters, per link i (1-based in names), in this order:
//   m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz
// where (mx, my, mz) = m c is the first moment (c the centre of mass in the link frame) and I is
// the rotational inertia about the link frame origin, in link-frame axes. SI units: kg, kg m,
// kg m^2.
// Each joint may add drive parameters, directly after its link's 10, in the column order of the
// drive-term table (core/drive_terms.hpp: Ia, Fv, Fc, Fo, Fa, Fs) and only the terms the model
// enables (DriveTerms). Joint-torque-sensor robots (Panda, KUKA LWR/iiwa) usually need fv,fc,fo;
// motor-current robots need ia too.
// Names carry the 1-based link index: m3, mx3, Ixx3, Ia3, Fv3.
//
// The paper's 7 parameters per link: m, cx, cy, cz (centre of mass, m) and the principal moments
// Ixx, Iyy, Izz of the inertia about the centre of mass, with axes parallel to the link frame and
// products of inertia zero.
#pragma once

#include <array>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "core/drive_terms.hpp"
#include "core/spatial.hpp"

namespace dynid {

inline constexpr int kLinkParameterCount = 10;
inline constexpr std::array<std::string_view, 10> kLinkParameterNames = {
    "m", "mx", "my", "mz", "Ixx", "Ixy", "Ixz", "Iyy", "Iyz", "Izz"};
/// The largest magnitude an inertial or drive parameter read from a file may have (kg, kg m,
/// kg m^2, N m s/rad, N m). The heaviest manipulator links weigh about 1e3 kg with inertias about
/// 1e3 kg m^2; 1e6 leaves three orders of margin, refuses unit slips such as g mm^2 (1e9 times
/// too large) and keeps every product in RNEA/ABA far from overflow.
inline constexpr double kMaxParameterMagnitude = 1e6;
/// The largest distance a model file may give (a placement, a DH length) [m], and the largest
/// gravity [m/s^2]: far beyond any manipulator and any planet, small enough that products in the
/// dynamics stay finite.
inline constexpr double kMaxModelLength = 1e6;
inline constexpr double kMaxGravity = 1e3;
inline constexpr int kPaperParameterCount = 7;
inline constexpr std::array<std::string_view, 7> kPaperParameterNames = {"m",   "cx",  "cy", "cz",
                                                                         "Ixx", "Iyy", "Izz"};

/// Which drive terms every joint of a model carries (the same set for all joints).
struct DriveTerms {
  unsigned mask = 0;  // bit k set: term k (DriveTerm) is enabled

  static constexpr DriveTerms none() { return {}; }
  /// ia,fv,fc: the `--drives` set of a robot that names none of its own.
  static constexpr DriveTerms rotorAndFriction() {
    return of({DriveTerm::kRotorInertia, DriveTerm::kViscous, DriveTerm::kCoulomb});
  }
  /// constexpr, so that a named set (kPuma560DriveTerms) is constant-initialised, never ordered
  /// against another translation unit's static initialisers.
  static constexpr DriveTerms of(std::initializer_list<DriveTerm> terms) {
    DriveTerms out;
    for (DriveTerm t : terms) out.mask |= 1u << static_cast<int>(t);
    return out;
  }
  constexpr bool has(DriveTerm t) const { return (mask >> static_cast<int>(t)) & 1u; }
  constexpr bool has(int k) const { return (mask >> k) & 1u; }
  constexpr bool any() const { return mask != 0; }
  /// Whether any inertial term (Ia: a mass-matrix diagonal) is enabled.
  bool inertial() const {
    for (int k = 0; k < kDriveTermCount; ++k)
      if (has(k) && kDriveTermTable[k].inertial) return true;
    return false;
  }
  /// Whether any term that is not inertial (friction, offset: anything but Ia) is enabled.
  bool friction() const {
    for (int k = 0; k < kDriveTermCount; ++k)
      if (has(k) && !kDriveTermTable[k].inertial) return true;
    return false;
  }
  int count() const {
    int n = 0;
    for (int k = 0; k < kDriveTermCount; ++k) n += has(k) ? 1 : 0;
    return n;
  }
  /// Position of term k among the enabled terms (0-based), or -1 when it is not enabled.
  int column(int k) const {
    if (!has(k)) return -1;
    int n = 0;
    for (int j = 0; j < k; ++j) n += has(j) ? 1 : 0;
    return n;
  }
  /// The term at position `column` among the enabled terms (0 <= column < count()).
  int termAt(int column) const {
    for (int k = 0; k < kDriveTermCount; ++k)
      if (has(k) && column-- == 0) return k;
    return -1;
  }
  bool operator==(const DriveTerms& other) const { return mask == other.mask; }
  bool operator!=(const DriveTerms& other) const { return mask != other.mask; }
};

/// "ia,fv,fc" (the enabled keys in column order), "none" when empty.
std::string driveTermsText(DriveTerms terms);
/// The enabled keys, in column order.
std::vector<std::string> driveTermsKeys(DriveTerms terms);
/// Parses a comma-separated list of keys ("fv,fc,fo", any order, no repeats) or "none". Throws
/// InputError naming the offending entry and listing the valid keys.
DriveTerms parseDriveTerms(std::string_view text);
/// "ia, fv, fc, fo, fa, fs": every key, for messages.
std::string driveTermKeyList();
/// One line per term, "ia rotor inertia (Ia ddq)": for help texts.
std::string driveTermHelp(std::string_view separator = ", ");

/// Which parameter columns a model carries per joint.
struct ParameterLayout {
  int num_links = 0;
  DriveTerms drives;  // the drive terms each joint adds after its link's 10

  int perLink() const { return kLinkParameterCount + drives.count(); }
  int size() const { return num_links * perLink(); }
  /// Index of link `link` (0-based) parameter `k` (0..9) in the standard vector.
  int linkIndex(int link, int k) const { return link * perLink() + k; }
  /// Index of drive term `k` (DriveTerm value) of joint `link` (0-based); the term must be enabled.
  int driveIndex(int link, int k) const {
    return link * perLink() + kLinkParameterCount + drives.column(k);
  }
  int driveIndex(int link, DriveTerm t) const { return driveIndex(link, static_cast<int>(t)); }
};

/// Names of the standard parameter vector, e.g. {"m1", "mx1", ..., "Izz1", "Ia1", ...}.
std::vector<std::string> standardParameterNames(const ParameterLayout& layout);
/// Names of the paper's 7-per-link vector, e.g. {"m1", "cx1", ..., "Izz1", "m2", ...}.
std::vector<std::string> paperParameterNames(int num_links);

/// Standard 10-vector [m, mx, my, mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz] of a rigid inertia.
template <typename Scalar>
Eigen::Matrix<Scalar, 10, 1> toStandardVector(const RigidInertia<Scalar>& inertia) {
  Eigen::Matrix<Scalar, 10, 1> p;
  const Matrix3<Scalar>& i = inertia.inertia;
  p << inertia.mass, inertia.first_moment.x(), inertia.first_moment.y(), inertia.first_moment.z(),
      i(0, 0), i(0, 1), i(0, 2), i(1, 1), i(1, 2), i(2, 2);
  return p;
}

/// Rigid inertia from a standard 10-vector (any Eigen expression of 10 entries).
template <typename Derived>
RigidInertia<typename Derived::Scalar> fromStandardVector(const Eigen::MatrixBase<Derived>& p) {
  using Scalar = typename Derived::Scalar;
  RigidInertia<Scalar> out;
  out.mass = p(0);
  out.first_moment << p(1), p(2), p(3);
  out.inertia << p(4), p(5), p(6), p(5), p(7), p(8), p(6), p(8), p(9);
  return out;
}

/// Paper 7-vector [m, cx, cy, cz, Ixx, Iyy, Izz] -> standard 10-vector, exactly:
/// h = m c, I_origin = diag(Ixx, Iyy, Izz) - m [c]x [c]x (parallel-axis theorem).
template <typename Derived>
Eigen::Matrix<typename Derived::Scalar, 10, 1> paperToStandard(
    const Eigen::MatrixBase<Derived>& p) {
  using Scalar = typename Derived::Scalar;
  const Scalar m = p(0);
  const Vector3<Scalar> c(p(1), p(2), p(3));
  RigidInertia<Scalar> out;
  out.mass = m;
  out.first_moment = m * c;
  const Matrix3<Scalar> sc = skew(c);
  out.inertia = Vector3<Scalar>(p(4), p(5), p(6)).asDiagonal();
  out.inertia -= m * (sc * sc);
  return toStandardVector(out);
}

/// Standard 10-vector -> paper 7-vector. Exact for inertias whose products about the centre of mass
/// are zero; otherwise the products are dropped and, when `dropped_products` is given, the largest
/// magnitude dropped is written there. A zero mass gives c = 0 (the first moment must then be 0).
Eigen::Matrix<double, 7, 1> standardToPaper(const Eigen::Matrix<double, 10, 1>& standard,
                                            double* dropped_products = nullptr);

/// Inertia about the centre of mass, in link axes: I_c = I_origin + [h]x[h]x / m (m > 0), or
/// I_origin when m == 0.
Eigen::Matrix3d inertiaAboutCom(const RigidInertia<double>& inertia);

/// One violated physical-consistency condition of one link.
struct ConsistencyViolation {
  int link = 0;           // 0-based
  std::string link_name;  // the model's name for the link
  std::string condition;  // e.g. "mass >= 0", "triangle inequality I1 + I2 >= I3"
  std::string detail;     // the numbers, e.g. "0 + 0 < 0.35"
};

/// Checks one link's 10 standard parameters for physical realisability: mass >= 0; a massless link
/// has no first moment; the inertia about the centre of mass is positive semi-definite; its
/// principal moments satisfy the triangle inequalities. `tolerance` is relative to the trace of
/// the inertia about the centre of mass (default: 1e-12, round-off of the conversions).
std::vector<ConsistencyViolation> checkPhysicalConsistency(const RigidInertia<double>& inertia,
                                                           int link, const std::string& link_name,
                                                           double tolerance = 1e-12);

/// Base-parameter coordinates beta = P theta: which combinations of the standard parameters the
/// torques (and the GC error) determine. identifiability's BaseParameters::coordinates() makes
/// them; the search and refinement modules take them, so they depend on core only.
struct BaseCoordinates {
  Eigen::MatrixXd projection;      // P, num_base x p
  std::vector<std::string> names;  // num_base names ("Izz1 + Ia1 + Iyy2", ...)
};

}  // namespace dynid
