// Contacts on a floating-base robot and their Jacobians (floating_model.hpp's velocity: the base
// twist (omega, v) in the base frame, then dq).
#pragma once

#include <string>
#include <vector>

#include "core/floating/floating_data.hpp"

namespace dynid {

/// Where the environment can push: a point (a foot's sole point, a force (3-D) through it) or a
/// frame (a flat foot or a wrench sensor: a wrench (6-D)) fixed on a body.
struct Contact {
  enum class Kind { kPoint, kFrame };
  std::string name;
  /// The body: -1 the base, else a limb body index.
  int body = -1;
  /// The contact frame in the body's link frame (a point contact uses its origin).
  Pose<double> placement;
  Kind kind = Kind::kPoint;
  /// 3 or 6: the dimension of the force the contact transmits.
  int dimension() const { return kind == Kind::kPoint ? 3 : 6; }
};

/// The contact's Jacobian ((3 or 6) x (6 + n)) in base-frame axes: a point's linear velocity, or
/// a frame's spatial velocity (omega, v of its origin), both in the base frame, as a linear map
/// of (nu, dq). Depends on q only. Throws InputError on a body index out of range or a q of
/// another size. Overwrites data.limbs' liMi and oMj (joint frames in the base frame).
Eigen::MatrixXd contactJacobian(const FloatingModel& model, FloatingData& data,
                                const Contact& contact, const Eigen::Ref<const Eigen::VectorXd>& q);

/// The contact frame's pose in the base frame at q (the same kinematics).
Pose<double> contactPose(const FloatingModel& model, FloatingData& data, const Contact& contact,
                         const Eigen::Ref<const Eigen::VectorXd>& q);

}  // namespace dynid
