// Template bodies of floating_regressor.hpp; include only to instantiate a new Scalar.
#pragma once

#include "core/floating/floating_regressor.hpp"
#include "core/floating/floating_rnea-inl.hpp"
#include "core/regressor-inl.hpp"

namespace dynid {

template <typename Scalar>
const MatrixX<Scalar>& floatingRegressor(const FloatingModelTpl<Scalar>& model,
                                         FloatingDataTpl<Scalar>& data,
                                         const BaseMotionTpl<Scalar>& base,
                                         const ConstVectorRef<Scalar>& q,
                                         const ConstVectorRef<Scalar>& dq,
                                         const ConstVectorRef<Scalar>& ddq) {
  checkFloatingData(model, data);
  const ModelTpl<Scalar>& limbs = model.limbs();
  DataTpl<Scalar>& ld = data.limbs;
  checkState(limbs, ld, q, dq, ddq, "ddq");
  floating_detail::forwardPass(model, data, base, q, dq, ddq);
  const int n = limbs.numJoints();
  const ParameterLayout layout = limbs.parameterLayout();
  const std::vector<int>& parents = limbs.parents();
  data.Y.setZero();
  // The base wrench's row k is the power of the unit base motion e_k: e_k^T A theta for the base
  // body, s^T A theta for a limb body with s = e_k expressed in its link frame (regressor-inl.hpp's
  // duality: one motion carried down instead of A's ten columns carried up).
  const regressor_detail::BodyRegressor<Scalar> base_body(data.base_v, data.base_a);
  Vector6<Scalar> e = Vector6<Scalar>::Zero();
  for (int k = 0; k < 6; ++k) {
    e[k] = Scalar(1);
    data.Y.row(k).template head<kLinkParameterCount>() = base_body.product(e).transpose();
    e[k] = Scalar(0);
  }
  for (int i = 0; i < n; ++i) {
    const int p = parents[i];
    ld.oMj[i] = p < 0 ? ld.liMi[i] : ld.oMj[p] * ld.liMi[i];
    const Pose<Scalar>& B = limbs.body_placements()[i];
    const regressor_detail::BodyRegressor<Scalar> A(B.actInvMotion(ld.v[i]),
                                                    B.actInvMotion(ld.a[i]));
    const int column = FloatingModelTpl<Scalar>::limbColumn(layout.linkIndex(i, 0));
    const Pose<Scalar> oMi = ld.oMj[i] * B;
    for (int k = 0; k < 6; ++k) {
      e[k] = Scalar(1);
      data.Y.row(k).template segment<kLinkParameterCount>(column) =
          A.product(oMi.actInvMotion(e)).transpose();
      e[k] = Scalar(0);
    }
    // The joint rows as jointTorqueRegressor fills them: S_j carried down to link frame i.
    const std::size_t row_i = static_cast<std::size_t>(i);
    ld.joint_axes[row_i * n + row_i] = jointMotionAt(limbs, i, Scalar(1));
    for (int j = p; j >= 0; j = parents[j])
      ld.joint_axes[static_cast<std::size_t>(j) * n + row_i] =
          ld.liMi[i].actInvMotion(ld.joint_axes[static_cast<std::size_t>(j) * n + p]);
    for (int j = i; j >= 0; j = parents[j])
      data.Y.row(6 + j).template segment<kLinkParameterCount>(column) =
          A.product(B.actInvMotion(ld.joint_axes[static_cast<std::size_t>(j) * n + row_i]))
              .transpose();
    const DriveTerms terms = limbs.driveTerms();
    for (int k = 0; k < kDriveTermCount; ++k)
      if (terms.has(k))
        data.Y(6 + i, FloatingModelTpl<Scalar>::limbColumn(layout.driveIndex(i, k))) =
            driveBasis(k, dq[i], ddq[i], limbs.restVelocity(i));
  }
  return data.Y;
}

}  // namespace dynid
