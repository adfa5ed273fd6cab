// The workspace of the floating-base algorithms (floating_model.hpp): the limbs' Data and the
// base body's quantities. Built once from a FloatingModel; the algorithms then allocate nothing.
#pragma once

#include <string>

#include <Eigen/Cholesky>

#include "core/checks.hpp"
#include "core/data.hpp"
#include "core/floating/floating_model.hpp"
#include "core/floating/lane_pairs.hpp"

namespace dynid {

template <typename Scalar>
using RowMatrixX = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The base's motion: its rotation (base to world, baseRotation of the quaternion), its twist
/// (omega, v) in the base frame and the twist's derivative (floating_model.hpp's conventions).
template <typename Scalar>
struct BaseMotionTpl {
  Matrix3<Scalar> rotation = Matrix3<Scalar>::Identity();
  Vector6<Scalar> twist = Vector6<Scalar>::Zero();
  Vector6<Scalar> acceleration = Vector6<Scalar>::Zero();
};
using BaseMotion = BaseMotionTpl<double>;

template <typename Scalar>
struct FloatingDataTpl {
  explicit FloatingDataTpl(const FloatingModelTpl<Scalar>& model)
      : limbs(model.limbs()),
        tau(VectorX<Scalar>::Zero(model.numVelocities())),
        acceleration(VectorX<Scalar>::Zero(model.numVelocities())),
        Y(RowMatrixX<Scalar>::Zero(model.numVelocities(), model.numParameters())),
        M(MatrixX<Scalar>::Zero(model.numVelocities(), model.numVelocities())),
        llt(model.numVelocities()),
        base_axes(static_cast<std::size_t>(model.numJoints()), Vector6<Scalar>::Zero()),
        motions(static_cast<std::size_t>(model.numJoints())),
        forces(static_cast<std::size_t>(model.numJoints())) {}

  /// The limbs' workspace: liMi, v, a, f in joint frames as the fixed-base algorithms keep them;
  /// oMj and oMi place joint and link frames in the base frame (floatingRegressor sets oMj).
  DataTpl<Scalar> limbs;
  /// The base body's twist, acceleration (gravity included, as a base acceleration of -g) and the
  /// force it needs, in the base frame.
  Vector6<Scalar> base_v = Vector6<Scalar>::Zero();
  Vector6<Scalar> base_a = Vector6<Scalar>::Zero();
  Vector6<Scalar> base_f = Vector6<Scalar>::Zero();
  /// The generalized force (floatingRnea): the base wrench (6), then the joint torques.
  VectorX<Scalar> tau;
  /// The generalized acceleration (floatingForwardDynamics): dnu (6), then ddq.
  VectorX<Scalar> acceleration;
  /// The regressor (floatingRegressor): (6 + n) x numParameters(), row-major (each body writes
  /// rows of ten contiguous entries).
  RowMatrixX<Scalar> Y;
  /// The mass matrix (floatingCrba): (6 + n) x (6 + n), the base's block first.
  MatrixX<Scalar> M;
  /// The whole robot's composite inertia in the base frame (floatingCrba).
  RigidInertia<Scalar> base_composite;
  /// floatingAba: the base's articulated inertia and bias force (the limbs' handed to it), base
  /// frame.
  Matrix6<Scalar> base_articulated = Matrix6<Scalar>::Zero();
  Vector6<Scalar> base_bias = Vector6<Scalar>::Zero();
  /// floatingForwardDynamics' factor of M.
  Eigen::LLT<MatrixX<Scalar>> llt;
  /// floatingRegressor: each joint's motion axis S_j in the base frame.
  std::vector<Vector6<Scalar>> base_axes;
  /// The forward pass (floatingRnea, floatingRegressor): each limb body's velocity and
  /// acceleration in its joint frame as lane pairs (lane_pairs.hpp), the base body's in the base
  /// frame.
  std::vector<MotionPair<Scalar>> motions;
  MotionPair<Scalar> base_motion;
  /// floatingRnea's backward pass: each limb body's force (moment, force) as lane pairs.
  std::vector<Pair3<Scalar>> forces;
};
using FloatingData = FloatingDataTpl<double>;

/// Throws InputError unless `data` was built for this model as it is now.
template <typename Scalar>
void checkFloatingData(const FloatingModelTpl<Scalar>& model, const FloatingDataTpl<Scalar>& data) {
  checkData(model.limbs(), data.limbs);
  const int nv = model.numVelocities();
  if (data.tau.size() != nv || data.acceleration.size() != nv || data.M.rows() != nv ||
      data.Y.rows() != nv || data.Y.cols() != model.numParameters())
    throw InputError("FloatingData was built for another model than '" + model.name() +
                     "', or before its drive terms changed");
}

}  // namespace dynid
