#pragma once

#include "core/checks.hpp"
#include "core/friction.hpp"
#include "core/regressor.hpp"

namespace dynid {

namespace regressor_detail {
/// The body regressor A (6 x 10) with I a + v x* (I v) = A theta_link for a body moving with
/// velocity v and acceleration a (both in its link frame), theta_link = [m, h, Ixx, Ixy, Ixz, Iyy,
/// Iyz, Izz]:
///   m:   (0, g),  g = a_l + w x v_l
///   h:   (M1, M2) = (-[a_l]x - [w]x[v_l]x + [v_l]x[w]x,  [dw]x + [w]x[w]x)
///   I_o: (N, 0) = (L(dw) + [w]x L(w), 0),  with I_o w = L(w) [Ixx, Ixy, Ixz, Iyy, Iyz, Izz].
/// Kept in the form its only use needs, s^T A for a motion s = (s_a, s_l), with A's zero blocks
/// skipped:
///   s^T A = [ s_l . g,  g x s_a + M2^T s_l,  N^T s_a ]
/// since M1^T = [a_l]x + [w]x[v_l]x - [v_l]x[w]x = [a_l]x + v_l w^T - w v_l^T = [g]x, and
/// M2^T = -[dw]x + w w^T - |w|^2 1 (regressor_test: Y theta = RNEA for random theta).
template <typename Scalar>
struct BodyRegressor {
  BodyRegressor(const Vector6<Scalar>& v, const Vector6<Scalar>& a)
      : BodyRegressor(Vector3<Scalar>(v.template head<3>()), Vector3<Scalar>(v.template tail<3>()),
                      Vector3<Scalar>(a.template head<3>()),
                      Vector3<Scalar>(a.template tail<3>())) {}
  /// From the halves: twist (w, vl) and its derivative (dw, al).
  DYNID_INLINE BodyRegressor(const Vector3<Scalar>& w, const Vector3<Scalar>& vl,
                             const Vector3<Scalar>& dw, const Vector3<Scalar>& al) {
    g = al + cross(w, vl);
    const Scalar xx = w.x() * w.x(), yy = w.y() * w.y(), zz = w.z() * w.z();
    const Scalar ww = xx + yy + zz;
    m2t(0, 0) = xx - ww, m2t(1, 1) = yy - ww, m2t(2, 2) = zz - ww;
    const Scalar xy = w.x() * w.y(), xz = w.x() * w.z(), yz = w.y() * w.z();
    m2t(0, 1) = xy + dw.z(), m2t(1, 0) = xy - dw.z();
    m2t(0, 2) = xz - dw.y(), m2t(2, 0) = xz + dw.y();
    m2t(1, 2) = yz + dw.x(), m2t(2, 1) = yz - dw.x();
    // Column k of N^T is N^T e_k = sym(e_k, dw) + sym(e_k x w, w), where sym(u, x) = [u0 x0,
    // u0 x1 + u1 x0, u0 x2 + u2 x0, u1 x1, u1 x2 + u2 x1, u2 x2] is u^T L(x) (and
    // s^T [w]x = (s x w)^T); written out, e_k's zeros dropped (IEEE arithmetic keeps 0 x as a
    // product), they share w's six products with M2.
    nt.col(0) << dw.x(), dw.y() - xz, dw.z() + xy, -yz, yy - zz, yz;
    nt.col(1) << xz, dw.x() + yz, zz - xx, dw.y(), dw.z() - xy, -xz;
    nt.col(2) << -xy, xx - yy, dw.x() - yz, xy, dw.y() + xz, dw.z();
  }
  /// A's non-zero blocks, for a caller that transforms A whole (the floating regressor's base
  /// rows): A = [[0, -[g]x, N], [g, M2, 0]].
  const Vector3<Scalar>& gTerm() const { return g; }
  auto m2() const { return m2t.transpose(); }
  auto n() const { return nt.transpose(); }
  /// s^T A for s = (e_k, 0), a unit rotation about axis k (0-2), into `row` (ten entries): (0, g x
  /// e_k, N^T's column k).
  template <typename Row>
  DYNID_INLINE void ownRevoluteRow(int k, Row&& row) const {
    row(0) = Scalar(0);
    row(1 + k) = Scalar(0);
    row(1 + (k + 1) % 3) = g[(k + 2) % 3];
    row(1 + (k + 2) % 3) = -g[(k + 1) % 3];
    row.template tail<6>() = nt.col(k);
  }
  /// s^T A as a column.
  Eigen::Matrix<Scalar, 10, 1> product(const Vector6<Scalar>& s) const {
    Eigen::Matrix<Scalar, 10, 1> out;
    const Vector3<Scalar> sa = s.template head<3>(), sl = s.template tail<3>();
    out(0) = sl.dot(g);
    out.template segment<3>(1) = cross(g, sa);
    out.template segment<3>(1).noalias() += m2t * sl;
    out.template tail<6>().noalias() = nt * sa;
    return out;
  }

 private:
  Vector3<Scalar> g;
  Matrix3<Scalar> m2t;
  Eigen::Matrix<Scalar, 6, 3> nt;
};
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
  base_acceleration << Scalar(0), Scalar(0), Scalar(0), -model.gravity();
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
    const regressor_detail::BodyRegressor<Scalar> A(B.actInvMotion(data.v[i]),
                                                    B.actInvMotion(data.a[i]));
    const std::size_t row_i = static_cast<std::size_t>(i);
    data.joint_axes[row_i * n + row_i] = jointMotionAt(model, i, Scalar(1));
    for (int j = parents[i]; j >= 0; j = parents[j])  // parents precede their children
      data.joint_axes[static_cast<std::size_t>(j) * n + row_i] =
          data.liMi[i].actInvMotion(data.joint_axes[static_cast<std::size_t>(j) * n + parents[i]]);
    const int column = layout.linkIndex(i, 0);
    for (int j = i; j >= 0; j = parents[j]) {
      const Vector6<Scalar> s =
          B.actInvMotion(data.joint_axes[static_cast<std::size_t>(j) * n + row_i]);
      data.Y.row(j).template segment<10>(column) = A.product(s).transpose();
    }
    const DriveTerms terms = model.driveTerms();
    if (!terms.any()) continue;
    // Drive columns act on joint i only: phi_k(dq_i, ddq_i) of the drive-term table.
    for (int k = 0; k < kDriveTermCount; ++k)
      if (terms.has(k))
        data.Y(i, layout.driveIndex(i, k)) = driveBasis(k, dq[i], ddq[i], model.restVelocity(i));
  }
  return data.Y;
}

}  // namespace dynid
