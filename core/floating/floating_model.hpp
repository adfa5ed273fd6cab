// A floating-base robot: a free-flyer joint (6 degrees of freedom) between the world and a base
// body, and the limbs (one-degree-of-freedom joints) hanging from that base. docs/FLOATING.md.
//
// Conventions (Featherstone's body coordinates, dynid's spatial order: angular first):
//   configuration  base position p (world frame, m), orientation a unit quaternion (w, x, y, z)
//                  that rotates base-frame vectors into the world frame (R = R(quaternion)),
//                  joint positions q (n);
//   velocity       the base twist nu = (omega, v) in the base frame: omega the angular velocity,
//                  v the velocity of the base origin, both in base-frame axes; joint rates dq;
//   acceleration   dnu = d/dt nu (the derivative of the base-frame coordinates; the base origin's
//                  classical acceleration is dv + omega x v), joint accelerations ddq;
//   generalized force  (w, tau): w = (n, f) the wrench on the base body about the base origin in
//                  base-frame axes that the motion needs from outside the robot (the contact
//                  wrenches, summed there), tau the joint torques.
// Pinocchio's free-flyer orders the velocity (v, omega) and the quaternion (x, y, z, w); the same
// quantities otherwise (docs/FLOATING.md gives the map).
//
// Standard parameters: the base body's 10 (named with link index 0: m0, mx0, ..., Izz0; inertia
// about the base origin in base-frame axes), then the limbs' standard vector (core/parameters.hpp:
// link i's 10, its drive terms). The limbs' Model keeps its own conventions: a body whose parent
// is -1 hangs from the base body, and its gravity is the world's (in world axes).
#pragma once

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/model-inl.hpp"
#include "core/model.hpp"

namespace dynid {

/// The largest departure of a base quaternion's norm from 1 that is taken as round-off (a log
/// that stores quaternions in single precision is within 1e-6; 1e-3 is a 0.1 % scale of every
/// rotation entry); within it the quaternion is normalised, beyond it refused (baseRotation).
inline constexpr double kQuaternionNormTolerance = 1e-3;

/// The rotation (base to world) of a quaternion given as (w, x, y, z). A quaternion whose norm is
/// within kQuaternionNormTolerance of 1 is normalised; any other norm, or a non-finite entry,
/// throws InputError naming `field` and the norm. Templated so a Jet quaternion rotates too (its
/// check is on the value).
template <typename Scalar>
Matrix3<Scalar> baseRotation(const Eigen::Matrix<Scalar, 4, 1>& wxyz,
                             const char* field = "base_orientation") {
  using std::abs;
  using std::sqrt;
  const Scalar norm = sqrt(wxyz.squaredNorm());
  const double value = model_detail::value(norm);
  if (!(abs(value - 1.0) <= kQuaternionNormTolerance))
    throw InputError(std::string("`") + field + "` is not a unit quaternion: its norm is " +
                     formatNumber(value, 6) +
                     " (columns in the order w, x, y, z; a norm within 1e-3 of 1 is normalised)");
  const Eigen::Quaternion<Scalar> quaternion(wxyz(0) / norm, wxyz(1) / norm, wxyz(2) / norm,
                                             wxyz(3) / norm);
  return quaternion.toRotationMatrix();
}

/// A named frame fixed on a body (a URDF link, moving or merged by a fixed joint): the body (-1
/// the base, else a limb body) and the frame's placement in that body's link frame.
struct BodyFrame {
  std::string name;
  int body = -1;
  Pose<double> placement;
};

/// A floating-base robot: the base body's inertia and the limbs' Model, both read-only once built.
template <typename Scalar>
class FloatingModelTpl {
 public:
  /// Named frames (contacts, sensors) on its bodies; they feed no computation but contacts'.
  std::vector<BodyFrame> frames;
  /// The frame of that name, or nullptr.
  const BodyFrame* findFrame(const std::string& name) const {
    for (const BodyFrame& f : frames)
      if (f.name == name) return &f;
    return nullptr;
  }

  /// The limbs (finalized; bodies with parent -1 hang from the base) and the base body's inertia
  /// in the base frame about its origin. Throws InputError when the limbs are not finalized or the
  /// base inertia has a non-finite entry or a negative mass.
  FloatingModelTpl(ModelTpl<Scalar> limbs, const RigidInertia<Scalar>& base_inertia,
                   std::string base_name = "base")
      : limbs_(std::move(limbs)), base_inertia_(base_inertia), base_name_(std::move(base_name)) {
    if (!limbs_.finalized())
      throw InputError("the limbs' model '" + limbs_.name + "' was not finalized");
    checkBaseInertia(base_inertia_);
    for (const Pose<Scalar>& B : limbs_.body_placements())
      plain_bodies_.push_back(model_detail::isIdentity(B) ? 1 : 0);
    setRevoluteAxes();
  }

  /// 1 where limb body i's link frame is its joint frame (body placement the identity: every URDF
  /// link), so the regressor skips that transform.
  const std::vector<char>& plainBodies() const { return plain_bodies_; }

  /// r (0-2) where limb joint i is revolute about +e_r or -e_r of its joint frame (URDF joints
  /// whose axis is negated, as half of ANYmal C's are), -1 otherwise; and that axis' sign (+-1).
  /// The floating kernels take these on the unit axis' fast path, the angle's sign folded in.
  const std::vector<int>& revoluteAxes() const { return revolute_axes_; }
  const std::vector<int>& axisSigns() const { return axis_signs_; }

  const ModelTpl<Scalar>& limbs() const { return limbs_; }
  const RigidInertia<Scalar>& baseInertia() const { return base_inertia_; }
  const std::string& baseName() const { return base_name_; }
  const std::string& name() const { return limbs_.name; }
  /// Gravity in the world frame [m/s^2] (the limbs' Model's).
  const Vector3<Scalar>& gravity() const { return limbs_.gravity(); }

  int numJoints() const { return limbs_.numJoints(); }
  /// 6 + numJoints(): the base twist's six and the joint rates.
  int numVelocities() const { return 6 + numJoints(); }
  /// 10 (the base body) + the limbs' standard parameters.
  int numParameters() const { return kLinkParameterCount + limbs_.parameterLayout().size(); }
  /// The column of limb parameter k (an index into the limbs' layout) in the floating vector.
  static int limbColumn(int k) { return kLinkParameterCount + k; }

  /// [base 10, limbs' standard vector].
  VectorX<Scalar> standardParameters() const {
    VectorX<Scalar> out(numParameters());
    out.template head<kLinkParameterCount>() = toStandardVector(base_inertia_);
    out.tail(numParameters() - kLinkParameterCount) = limbs_.standardParameters();
    return out;
  }
  /// Sets every parameter from a floating standard vector. Throws InputError on a size mismatch
  /// or a base inertia setStandardParameters's checks refuse.
  void setStandardParameters(const VectorX<Scalar>& theta) {
    if (theta.size() != numParameters())
      throw InputError("a floating-base parameter vector needs " + std::to_string(numParameters()) +
                       " entries, not " + std::to_string(theta.size()));
    const RigidInertia<Scalar> base =
        fromStandardVector(theta.template head<kLinkParameterCount>());
    checkBaseInertia(base);
    limbs_.setStandardParameters(theta.tail(numParameters() - kLinkParameterCount));
    base_inertia_ = base;
  }
  void setBaseInertia(const RigidInertia<Scalar>& inertia) {
    checkBaseInertia(inertia);
    base_inertia_ = inertia;
  }
  /// Sets which drive terms the limbs' joints carry (ModelTpl::setDriveTerms; build the data
  /// after it).
  void setDriveTerms(DriveTerms terms) { limbs_.setDriveTerms(terms); }

  template <typename NewScalar>
  FloatingModelTpl<NewScalar> cast() const {
    FloatingModelTpl<NewScalar> out(limbs_.template cast<NewScalar>(),
                                    base_inertia_.template cast<NewScalar>(), base_name_);
    out.frames = frames;
    return out;
  }

 private:
  static void checkBaseInertia(const RigidInertia<Scalar>& inertia) {
    const Eigen::Matrix<Scalar, 10, 1> p = toStandardVector(inertia);
    for (int k = 0; k < kLinkParameterCount; ++k)
      if (!std::isfinite(model_detail::value(p[k])))
        throw InputError("the base body's " + std::string(kLinkParameterNames[k]) +
                         " is not finite");
    if (model_detail::value(inertia.mass) < 0.0)
      throw InputError("the base body's mass is negative");
  }

  void setRevoluteAxes() {
    for (int i = 0; i < limbs_.numJoints(); ++i) {
      int axis = -1, sign = 1;
      if (limbs_.joint_types()[i] != JointType::kPrismatic) {
        const Vector3<Scalar>& a = limbs_.axes()[i];
        const Eigen::Vector3d e(model_detail::value(a.x()), model_detail::value(a.y()),
                                model_detail::value(a.z()));
        for (int r = 0; r < 3; ++r) {
          if (e == Eigen::Vector3d::Unit(r)) axis = r;
          if (e == -Eigen::Vector3d::Unit(r)) axis = r, sign = -1;
        }
      }
      revolute_axes_.push_back(axis);
      axis_signs_.push_back(sign);
    }
  }

  ModelTpl<Scalar> limbs_;
  std::vector<char> plain_bodies_;
  std::vector<int> revolute_axes_, axis_signs_;
  RigidInertia<Scalar> base_inertia_;
  std::string base_name_;
};

using FloatingModel = FloatingModelTpl<double>;

/// The floating standard parameters' names: m0 ... Izz0 (the base body), then the limbs'.
std::vector<std::string> floatingParameterNames(const FloatingModel& model);

}  // namespace dynid
