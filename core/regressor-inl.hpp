#pragma once

#include "core/checks.hpp"
#include "core/friction.hpp"
#include "core/regressor.hpp"

namespace dynid {

namespace regressor_detail {
/// The 6 x 10 matrix A with I a + v x* (I v) = A theta_link for a body moving with velocity v and
/// acceleration a (both in its link frame), theta_link = [m, h, Ixx, Ixy, Ixz, Iyy, Iyz, Izz]:
///   m:   (0, a_l + w x v_l)
///   h:   (-[a_l]x - [w]x[v_l]x + [v_l]x[w]x,  [dw]x + [w]x[w]x)
///   I_o: (L(dw) + [w]x L(w), 0),  with I_o w = L(w) [Ixx, Ixy, Ixz, Iyy, Iyz, Izz].
template <typename Scalar>
Eigen::Matrix<Scalar, 6, 10> bodyRegressor(const Vector6<Scalar>& v, const Vector6<Scalar>& a) {
  const Vector3<Scalar> w = v.template head<3>(), vl = v.template tail<3>();
  const Vector3<Scalar> dw = a.template head<3>(), al = a.template tail<3>();
  const Matrix3<Scalar> sw = skew(w), sv = skew(vl);
  auto L = [](const Vector3<Scalar>& x) {
    Eigen::Matrix<Scalar, 3, 6> out = Eigen::Matrix<Scalar, 3, 6>::Zero();
    out(0, 0) = x.x(), out(0, 1) = x.y(), out(0, 2) = x.z();
    out(1, 1) = x.x(), out(1, 3) = x.y(), out(1, 4) = x.z();
    out(2, 2) = x.x(), out(2, 4) = x.y(), out(2, 5) = x.z();
    return out;
  };
  Eigen::Matrix<Scalar, 6, 10> A = Eigen::Matrix<Scalar, 6, 10>::Zero();
  A.template block<3, 1>(3, 0) = al + cross(w, vl);
  A.template block<3, 3>(0, 1) = -skew(al) - sw * sv + sv * sw;
  A.template block<3, 3>(3, 1) = skew(dw) + sw * sw;
  A.template block<3, 6>(0, 4) = L(dw) + sw * L(w);
  return A;
}
}  // namespace regressor_detail

template <typename Scalar>
const MatrixX<Scalar>& jointTorqueRegressor(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                                            const ConstVectorRef<Scalar>& q,
                                            const ConstVectorRef<Scalar>& dq,
                                            const ConstVectorRef<Scalar>& ddq) {
  checkState(model, data, q, dq, ddq, "ddq");
  const int n = model.numJoints();
  const ParameterLayout layout = model.parameterLayout();
  Vector6<Scalar> base_acceleration;
  base_acceleration << Scalar(0), Scalar(0), Scalar(0), -model.gravity;
  data.Y.setZero();
  // Velocities and accelerations in joint frames, as in rnea (gravity as a base acceleration);
  // the joint transforms first, so their sin/cos calls overlap.
  for (int i = 0; i < n; ++i) setJointTransform(model, i, q[i], data.liMi[i]);
  for (int i = 0; i < n; ++i) {
    const Pose<Scalar>& X = data.liMi[i];
    const int p = model.parents()[i];
    if (p < 0) {
      data.v[i] = jointMotionAt(model, i, dq[i]);
      data.a[i] = X.actInvMotion(base_acceleration);
    } else {
      data.v[i] = X.actInvMotion(data.v[p]);
      addJointMotion(model, i, dq[i], data.v[i]);
      data.a[i] = X.actInvMotion(data.a[p]) + crossJointMotion(model, i, data.v[i], dq[i]);
    }
    addJointMotion(model, i, ddq[i], data.a[i]);
  }
  const std::vector<int>& parents = model.parents();
  for (int i = 0; i < n; ++i) {
    // Body i's force in its link frame is A theta_i. Joint j (i or an ancestor) feels
    // S_j^T jXi* B* A theta_i; by duality (power is frame-independent) that is s^T A theta_i with
    // s = S_j carried down to link frame i as a motion. One 6-vector per (j, i) pair moves down
    // the chain, instead of A's ten columns moving up it.
    const Pose<Scalar>& B = model.body_placements()[i];
    const Eigen::Matrix<Scalar, 6, 10> A = regressor_detail::bodyRegressor<Scalar>(
        B.actInvMotion(data.v[i]), B.actInvMotion(data.a[i]));
    const std::size_t row_i = static_cast<std::size_t>(i);
    data.joint_axes[row_i * n + row_i] = jointMotionAt(model, i, Scalar(1));
    for (int j = parents[i]; j >= 0; j = parents[j])  // parents precede their children
      data.joint_axes[static_cast<std::size_t>(j) * n + row_i] =
          data.liMi[i].actInvMotion(data.joint_axes[static_cast<std::size_t>(j) * n + parents[i]]);
    const int column = layout.linkIndex(i, 0);
    for (int j = i; j >= 0; j = parents[j]) {
      const Vector6<Scalar> s =
          B.actInvMotion(data.joint_axes[static_cast<std::size_t>(j) * n + row_i]);
      data.Y.row(j).template segment<10>(column) = s.transpose() * A;
    }
    const DriveTerms terms = model.drive_terms;
    if (!terms.any()) continue;
    // Drive columns act on joint i only: ddq, dq, sign(dq), 1, |sign(dq)| (parameters.hpp).
    const Scalar s = signum(dq[i]);
    if (terms.has(DriveTerm::kRotorInertia)) data.Y(i, layout.driveIndex(i, 0)) = ddq[i];
    if (terms.has(DriveTerm::kViscous)) data.Y(i, layout.driveIndex(i, 1)) = dq[i];
    if (terms.has(DriveTerm::kCoulomb)) data.Y(i, layout.driveIndex(i, 2)) = s;
    if (terms.has(DriveTerm::kOffset)) data.Y(i, layout.driveIndex(i, 3)) = Scalar(1);
    if (terms.has(DriveTerm::kCoulombAsymmetry)) data.Y(i, layout.driveIndex(i, 4)) = s * s;
  }
  return data.Y;
}

}  // namespace dynid
