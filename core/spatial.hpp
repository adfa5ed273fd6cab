// Spatial algebra (Featherstone), templated on Scalar so ceres::Jet flows through it.
//
// Conventions used everywhere in dynid:
//   - A spatial motion vector is [angular; linear] (omega, v), 6x1; a spatial force is
//     [moment; force] (n, f). Both are expressed in some body frame and taken at its origin.
//   - A Pose (R, p) places a child frame in a parent frame: x_parent = R x_child + p.
//   - A RigidInertia holds the 10 standard inertial parameters of a body in its own frame:
//     mass m, first moment h = m c (c the centre of mass), and the rotational inertia I about the
//     frame origin (not about the centre of mass).
#pragma once

#include <Eigen/Core>

// Small spatial operations sit on the hot path of every recursive algorithm: force inlining.
#if defined(__GNUC__)
#define DYNID_INLINE inline __attribute__((always_inline))
#define DYNID_NOINLINE __attribute__((noinline))
// Inline every call in the function's body (Eigen's loops over a user scalar type such as Lanes
// are otherwise left as calls).
#define DYNID_FLATTEN __attribute__((flatten))
#else
#define DYNID_INLINE inline
#define DYNID_NOINLINE
#define DYNID_FLATTEN
#endif

namespace dynid {

template <typename Scalar>
using Vector3 = Eigen::Matrix<Scalar, 3, 1>;
template <typename Scalar>
using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;
template <typename Scalar>
using Vector6 = Eigen::Matrix<Scalar, 6, 1>;
template <typename Scalar>
using Matrix6 = Eigen::Matrix<Scalar, 6, 6>;
template <typename Scalar>
using VectorX = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
template <typename Scalar>
using MatrixX = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

/// s = sin x, c = cos x (a Scalar type may compute both at once: core/lanes.hpp).
template <typename Scalar>
DYNID_INLINE void sinCos(const Scalar& x, Scalar& s, Scalar& c) {
  using std::cos;
  using std::sin;
  s = sin(x);
  c = cos(x);
}

/// Cross product a x b of two 3-vectors (any Eigen expressions; avoids including Eigen/Geometry).
template <typename A, typename B>
DYNID_INLINE Vector3<typename A::Scalar> cross(const Eigen::MatrixBase<A>& a,
                                               const Eigen::MatrixBase<B>& b) {
  return Vector3<typename A::Scalar>(a.y() * b.z() - a.z() * b.y(), a.z() * b.x() - a.x() * b.z(),
                                     a.x() * b.y() - a.y() * b.x());
}

/// The skew-symmetric matrix [a]x with [a]x b = a x b.
template <typename Scalar>
DYNID_INLINE Matrix3<Scalar> skew(const Vector3<Scalar>& a) {
  Matrix3<Scalar> s;
  s << Scalar(0), -a.z(), a.y(), a.z(), Scalar(0), -a.x(), -a.y(), a.x(), Scalar(0);
  return s;
}

/// Rotation by angle `angle` [rad] about the unit axis `axis` (Rodrigues' formula).
template <typename Scalar>
Matrix3<Scalar> axisAngle(const Vector3<Scalar>& axis, const Scalar& angle) {
  using std::cos;
  using std::sin;
  const Scalar s = sin(angle), c = cos(angle);
  const Matrix3<Scalar> k = skew(axis);
  return Matrix3<Scalar>::Identity() + s * k + (Scalar(1) - c) * (k * k);
}

/// Rotation from roll, pitch, yaw (URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll)).
template <typename Scalar>
Matrix3<Scalar> rotationFromRpy(const Scalar& roll, const Scalar& pitch, const Scalar& yaw) {
  using std::cos;
  using std::sin;
  const Scalar cr = cos(roll), sr = sin(roll), cp = cos(pitch), sp = sin(pitch), cy = cos(yaw),
               sy = sin(yaw);
  Matrix3<Scalar> r;
  r << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return r;
}

/// Roll, pitch, yaw of a rotation (inverse of rotationFromRpy; pitch in [-pi/2, pi/2]).
inline Eigen::Vector3d rpyFromRotation(const Eigen::Matrix3d& r) {
  using std::atan2;
  using std::sqrt;
  const double pitch = atan2(-r(2, 0), sqrt(r(0, 0) * r(0, 0) + r(1, 0) * r(1, 0)));
  const double roll = atan2(r(2, 1), r(2, 2));
  const double yaw = atan2(r(1, 0), r(0, 0));
  return {roll, pitch, yaw};
}

/// R^T x for a rotation R and a 3-vector x (any Eigen expression), written out: Eigen's fixed-size
/// product is not always inlined into large callers (the regressor), and a call per product costs
/// more than its nine multiplications.
template <typename R, typename X>
DYNID_INLINE Vector3<typename R::Scalar> transposeTimes(const Eigen::MatrixBase<R>& r,
                                                        const Eigen::MatrixBase<X>& x) {
  return Vector3<typename R::Scalar>(r(0, 0) * x.x() + r(1, 0) * x.y() + r(2, 0) * x.z(),
                                     r(0, 1) * x.x() + r(1, 1) * x.y() + r(2, 1) * x.z(),
                                     r(0, 2) * x.x() + r(1, 2) * x.y() + r(2, 2) * x.z());
}

/// Rigid placement of a child frame in a parent frame: x_parent = rotation * x_child + translation.
template <typename Scalar>
struct Pose {
  Matrix3<Scalar> rotation = Matrix3<Scalar>::Identity();
  Vector3<Scalar> translation = Vector3<Scalar>::Zero();

  static Pose Identity() { return Pose(); }

  /// Composition: (this * other) places other's child in this pose's parent frame.
  DYNID_INLINE Pose operator*(const Pose& other) const {
    Pose out;
    out.rotation.noalias() = rotation * other.rotation;
    out.translation.noalias() = rotation * other.translation;
    out.translation += translation;
    return out;
  }
  Pose inverse() const {
    Pose out;
    out.rotation = rotation.transpose();
    out.translation.noalias() = -(out.rotation * translation);
    return out;
  }

  /// Motion vector given in the child frame, expressed in the parent frame.
  DYNID_INLINE Vector6<Scalar> actMotion(const Vector6<Scalar>& m) const {
    Vector6<Scalar> out;
    out.template head<3>().noalias() = rotation * m.template head<3>();
    out.template tail<3>().noalias() = rotation * m.template tail<3>();
    out.template tail<3>() += cross(translation, out.template head<3>());
    return out;
  }
  /// Motion vector given in the parent frame, expressed in the child frame.
  DYNID_INLINE Vector6<Scalar> actInvMotion(const Vector6<Scalar>& m) const {
    Vector6<Scalar> out;
    out.template head<3>() = transposeTimes(rotation, m.template head<3>());
    const Vector3<Scalar> v = m.template tail<3>() - cross(translation, m.template head<3>());
    out.template tail<3>() = transposeTimes(rotation, v);
    return out;
  }
  /// Force vector given in the child frame, expressed in the parent frame.
  DYNID_INLINE Vector6<Scalar> actForce(const Vector6<Scalar>& f) const {
    Vector6<Scalar> out;
    out.template tail<3>().noalias() = rotation * f.template tail<3>();
    out.template head<3>().noalias() = rotation * f.template head<3>();
    out.template head<3>() += cross(translation, out.template tail<3>());
    return out;
  }

  template <typename NewScalar>
  Pose<NewScalar> cast() const {
    Pose<NewScalar> out;
    out.rotation = rotation.template cast<NewScalar>();
    out.translation = translation.template cast<NewScalar>();
    return out;
  }
};

/// Spatial cross product for motions: m1 x m2.
template <typename Scalar>
DYNID_INLINE Vector6<Scalar> crossMotion(const Vector6<Scalar>& m1, const Vector6<Scalar>& m2) {
  Vector6<Scalar> out;
  out.template head<3>() = cross(m1.template head<3>(), m2.template head<3>());
  out.template tail<3>() = cross(m1.template head<3>(), m2.template tail<3>()) +
                           cross(m1.template tail<3>(), m2.template head<3>());
  return out;
}

/// Spatial cross product of a motion with a force: m x* f.
template <typename Scalar>
DYNID_INLINE Vector6<Scalar> crossForce(const Vector6<Scalar>& m, const Vector6<Scalar>& f) {
  Vector6<Scalar> out;
  out.template head<3>() = cross(m.template head<3>(), f.template head<3>()) +
                           cross(m.template tail<3>(), f.template tail<3>());
  out.template tail<3>() = cross(m.template head<3>(), f.template tail<3>());
  return out;
}

/// Rigid-body inertia from the 10 standard parameters, in the body's frame, about its origin.
template <typename Scalar>
struct RigidInertia {
  Scalar mass = Scalar(0);
  Vector3<Scalar> first_moment = Vector3<Scalar>::Zero();  // h = m c [kg m]
  Matrix3<Scalar> inertia = Matrix3<Scalar>::Zero();       // about the origin [kg m^2]

  /// Momentum (force-type vector) of the body moving with spatial velocity m: I * m.
  DYNID_INLINE Vector6<Scalar> apply(const Vector6<Scalar>& m) const {
    const auto w = m.template head<3>();
    const auto v = m.template tail<3>();
    Vector6<Scalar> out;
    out.template head<3>().noalias() = inertia * w;
    out.template head<3>() += cross(first_moment, v);
    out.template tail<3>() = mass * v - cross(first_moment, w);
    return out;
  }

  /// This inertia (given in the child frame of `pose`) expressed in the parent frame.
  RigidInertia transformedBy(const Pose<Scalar>& pose) const {
    RigidInertia out;
    out.mass = mass;
    const Vector3<Scalar> hr = pose.rotation * first_moment;
    const Vector3<Scalar>& p = pose.translation;
    out.first_moment = hr + mass * p;
    // I' = R I R^T - m [p]x[p]x - [p]x[hr]x - [hr]x[p]x  (parallel-axis theorem), expanded with
    // [a]x[b]x = b a^T - (a.b) 1:  I' = R I R^T + (m |p|^2 + 2 p.hr) 1 - m p p^T - hr p^T - p hr^T.
    Matrix3<Scalar> half;
    half.noalias() = pose.rotation * inertia;
    out.inertia.noalias() = half * pose.rotation.transpose();
    out.inertia.noalias() -= (mass * p + hr) * p.transpose();
    out.inertia.noalias() -= p * hr.transpose();
    out.inertia.diagonal().array() += mass * p.squaredNorm() + Scalar(2) * p.dot(hr);
    return out;
  }

  RigidInertia& operator+=(const RigidInertia& other) {
    mass += other.mass;
    first_moment += other.first_moment;
    inertia += other.inertia;
    return *this;
  }

  /// The 6x6 spatial inertia matrix [[I, [h]x], [[h]x^T, m 1]].
  Matrix6<Scalar> matrix() const {
    Matrix6<Scalar> out;
    const Matrix3<Scalar> sh = skew(first_moment);
    out.template topLeftCorner<3, 3>() = inertia;
    out.template topRightCorner<3, 3>() = sh;
    out.template bottomLeftCorner<3, 3>() = sh.transpose();
    out.template bottomRightCorner<3, 3>() = mass * Matrix3<Scalar>::Identity();
    return out;
  }

  template <typename NewScalar>
  RigidInertia<NewScalar> cast() const {
    RigidInertia<NewScalar> out;
    out.mass = NewScalar(mass);
    out.first_moment = first_moment.template cast<NewScalar>();
    out.inertia = inertia.template cast<NewScalar>();
    return out;
  }
};

}  // namespace dynid
