// Template bodies of floating_regressor.hpp; include only to instantiate a new Scalar.
#pragma once

#include "core/floating/floating_regressor.hpp"
#include "core/floating/floating_rnea-inl.hpp"
#include "core/regressor-inl.hpp"

namespace dynid {

namespace floating_detail {
/// A body's force regressor in the base frame, row-major so that its rows are Y's.
template <typename Scalar>
using ForceRows = Eigen::Matrix<Scalar, 6, 10, Eigen::RowMajor>;

/// Y's six base rows over one body's ten columns: its body regressor A carried to the base frame
/// as a force by `X` (the body's link frame in the base frame); returns that 6 x 10 block F. F's
/// lower right 3 x 6 block is zero: neither computed nor written (Y's entries there are zero
/// from the Data's construction).
template <typename Scalar>
DYNID_INLINE ForceRows<Scalar> setBaseRows(const regressor_detail::BodyRegressor<Scalar>& A,
                                           const Pose<Scalar>& X, int column,
                                           RowMatrixX<Scalar>& Y) {
  const Matrix3<Scalar>& R = X.rotation;
  const Vector3<Scalar>& t = X.translation;
  const Vector3<Scalar> rg = R * A.gTerm();
  const Matrix3<Scalar> rm2 = R * A.m2();
  ForceRows<Scalar> F;
  // R (-[g]x) column c is -R (g x e_c) = (R g) x (R e_c)... written as R's columns crossed: R (e_c
  // x g) = (R e_c) x (R g).
  for (int c = 0; c < 3; ++c) {
    const Vector3<Scalar> top =
        cross(Vector3<Scalar>(R.col(c)), rg) + cross(t, Vector3<Scalar>(rm2.col(c)));
    F.template block<3, 1>(0, 1 + c) = top;
  }
  F.template block<3, 1>(0, 0) = cross(t, rg);
  // R N, N = A.n() (3 x 6): row r is R's row r combining N^T's columns.
  const auto nt = A.n().transpose();
  for (int r = 0; r < 3; ++r)
    F.template block<1, 6>(r, 4) = R(r, 0) * nt.col(0).transpose() +
                                   R(r, 1) * nt.col(1).transpose() +
                                   R(r, 2) * nt.col(2).transpose();
  F.template block<3, 1>(3, 0) = rg;
  F.template block<3, 3>(3, 1) = rm2;
  Y.template block<3, 10>(0, column) = F.template topRows<3>();
  Y.template block<3, 4>(3, column) = F.template block<3, 4>(3, 0);
  return F;
}

/// A body's regressor in its link frame from its halves in the joint frame, B the link frame in
/// the joint frame.
template <typename Scalar>
regressor_detail::BodyRegressor<Scalar> linkRegressor(const Pose<Scalar>& B,
                                                      const Vector3<Scalar>& w,
                                                      const Vector3<Scalar>& v,
                                                      const Vector3<Scalar>& dw,
                                                      const Vector3<Scalar>& dv) {
  Vector6<Scalar> vel, acc;
  vel << w, v;
  acc << dw, dv;
  return regressor_detail::BodyRegressor<Scalar>(B.actInvMotion(vel), B.actInvMotion(acc));
}

/// Joint i's motion axis S_i in the base frame, X its joint frame there: a revolute e_k is (R e_k,
/// t x R e_k), R's column k.
template <typename Scalar>
DYNID_INLINE void setBaseAxis(const FloatingModelTpl<Scalar>& model, int i, const Pose<Scalar>& X,
                              Vector6<Scalar>& axis) {
  const int k = model.revoluteAxes()[i];
  if (k < 0) {
    axis = X.actMotion(jointMotionAt(model.limbs(), i, Scalar(1)));
    return;
  }
  const Vector3<Scalar> r = model.axisSigns()[i] > 0 ? Vector3<Scalar>(X.rotation.col(k))
                                                     : Vector3<Scalar>(-X.rotation.col(k));
  axis.template head<3>() = r;
  axis.template tail<3>() = cross(X.translation, r);
}

/// s^T F into `row` (ten entries), F a force regressor from setBaseRows: its lower right 3 x 6
/// block is zero, so the inertia's six columns read s's angular half alone (42 products, not 60),
/// each a combination of F's rows.
template <typename Scalar, typename Row>
DYNID_INLINE void setJointRow(const Vector6<Scalar>& s, const ForceRows<Scalar>& F, Row&& row) {
  Eigen::Matrix<Scalar, 1, 10> out = s[0] * F.row(0) + s[1] * F.row(1) + s[2] * F.row(2);
  out.template head<4>() += s[3] * F.template block<1, 4>(3, 0) +
                            s[4] * F.template block<1, 4>(4, 0) +
                            s[5] * F.template block<1, 4>(5, 0);
  row = out;
}

/// Joint i's own row over body i's columns: S_i^T A in the link frame (X* is X^-T, so S^T X* A =
/// (X^-1 S)^T A), where a revolute axis e_k reads two entries of g and a column of N^T.
template <typename Scalar, typename Row>
DYNID_INLINE void setOwnRow(const FloatingModelTpl<Scalar>& model, int i, bool plain,
                            const regressor_detail::BodyRegressor<Scalar>& A, Row&& row) {
  const int r = model.revoluteAxes()[i];
  if (plain && r >= 0) {
    A.ownRevoluteRow(r, row);
    if (model.axisSigns()[i] < 0) row = -row;
    return;
  }
  const ModelTpl<Scalar>& limbs = model.limbs();
  const Vector6<Scalar> s = jointMotionAt(limbs, i, Scalar(1));
  row = A.product(plain ? s : limbs.body_placements()[i].actInvMotion(s)).transpose();
}
}  // namespace floating_detail

// Flattened, as floatingRnea.
template <typename Scalar>
DYNID_FLATTEN const RowMatrixX<Scalar>& floatingRegressor(const FloatingModelTpl<Scalar>& model,
                                                          FloatingDataTpl<Scalar>& data,
                                                          const BaseMotionTpl<Scalar>& base,
                                                          const ConstVectorRef<Scalar>& q,
                                                          const ConstVectorRef<Scalar>& dq,
                                                          const ConstVectorRef<Scalar>& ddq) {
  const ModelTpl<Scalar>& limbs = model.limbs();
  DataTpl<Scalar>& ld = data.limbs;
  const ParameterLayout layout = limbs.parameterLayout();
  const std::vector<int>& parents = limbs.parents();
  const DriveTerms terms = limbs.driveTerms();
  // No setZero: the entries this function never writes (a joint's row over a body outside its
  // subtree, a drive column's other rows) are structural zeros, zero since the Data was built
  // (95 KB a call on Romeo otherwise).
  // The base wrench's rows: each body's force A theta (A its body regressor, in its link frame)
  // carried to the base frame as a force, X* A = [[R A_n + t x R A_f], [R A_f]] with A's blocks
  // [[0, -[g]x, N], [g, M2, 0]] (regressor-inl.hpp) and (R, t) the link frame in the base frame.
  // Each body's columns are filled as the forward pass reaches it.
  const auto perBody = [&](int i, const MotionPair<Scalar>& m) DYNID_INLINE_LAMBDA {
    if (i < 0) {  // the base body, in the base frame: its columns' base rows alone
      floating_detail::setBaseRows(
          regressor_detail::BodyRegressor<Scalar>(data.base_v, data.base_a), Pose<Scalar>(), 0,
          data.Y);
      return;
    }
    const int p = parents[i];
    ld.oMj[i] = p < 0 ? ld.liMi[i] : ld.oMj[p] * ld.liMi[i];
    const Pose<Scalar>& B = limbs.body_placements()[i];
    const bool plain = model.plainBodies()[static_cast<std::size_t>(i)] != 0;
    const int column = FloatingModelTpl<Scalar>::limbColumn(layout.linkIndex(i, 0));
    const Vector3<Scalar> w = m.angular.lane(0), v = m.linear.lane(0);
    const Vector3<Scalar> dw = m.angular.lane(1), dv = m.linear.lane(1);
    const regressor_detail::BodyRegressor<Scalar> A =
        plain ? regressor_detail::BodyRegressor<Scalar>(w, v, dw, dv)
              : floating_detail::linkRegressor(B, w, v, dw, dv);
    const floating_detail::ForceRows<Scalar> F =
        plain ? floating_detail::setBaseRows(A, ld.oMj[i], column, data.Y)
              : floating_detail::setBaseRows(A, Pose<Scalar>(ld.oMj[i] * B), column, data.Y);
    // Joint j's row (j = i or an ancestor) is S_j^T jXi* A = (S_j in the base frame)^T F, by
    // duality: F is body i's force regressor in the base frame; joint i's own, S_i^T A.
    floating_detail::setBaseAxis(model, i, ld.oMj[i], data.base_axes[static_cast<std::size_t>(i)]);
    floating_detail::setOwnRow(model, i, plain, A,
                               data.Y.row(6 + i).template segment<kLinkParameterCount>(column));
    for (int j = parents[i]; j >= 0; j = parents[j])
      floating_detail::setJointRow(data.base_axes[static_cast<std::size_t>(j)], F,
                                   data.Y.row(6 + j).template segment<kLinkParameterCount>(column));
    for (int k = 0; k < kDriveTermCount; ++k)
      if (terms.has(k))
        data.Y(6 + i, FloatingModelTpl<Scalar>::limbColumn(layout.driveIndex(i, k))) =
            driveBasis(k, dq[i], ddq[i], limbs.restVelocity(i));
  };
  floating_detail::forwardPass(model, data, base, q, dq, ddq, perBody);
  return data.Y;
}

}  // namespace dynid
