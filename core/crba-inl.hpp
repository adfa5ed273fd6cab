#pragma once

#include "core/checks.hpp"
#include "core/crba.hpp"
#include "core/friction.hpp"

namespace dynid {

namespace crba_detail {
/// CRBA from the joint transforms already in data.liMi (set by crba or rnea).
template <typename Scalar>
void massMatrixFromTransforms(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data) {
  const int n = model.numJoints();
  for (int i = 0; i < n; ++i) data.composite[i] = model.frame_inertias()[i];
  // Composite inertias: Ic_p += pXi* Ic_i iXp.
  for (int i = n - 1; i >= 0; --i) {
    const int p = model.parents()[i];
    if (p >= 0) data.composite[p] += data.composite[i].transformedBy(data.liMi[i]);
  }
  // M_ij = S_j^T (jXi* Ic_i S_i) for every ancestor j of i; other entries are zero.
  data.M.setZero();
  for (int i = 0; i < n; ++i) {
    Vector6<Scalar> F = data.composite[i].apply(model.motion_subspaces()[i]);
    data.M(i, i) = projectOnJoint(model, i, F);
    if (model.driveTerms().inertial()) data.M(i, i) += driveInertia(model, i);
    for (int j = i; model.parents()[j] >= 0;) {
      F = data.liMi[j].actForce(F);
      j = model.parents()[j];
      data.M(j, i) = data.M(i, j) = projectOnJoint(model, j, F);
    }
  }
}
}  // namespace crba_detail

template <typename Scalar>
const MatrixX<Scalar>& crba(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                            const ConstVectorRef<Scalar>& q) {
  checkData(model, data);
  checkSize(model, q, "q");
  for (int i = 0; i < model.numJoints(); ++i) setJointTransform(model, i, q[i], data.liMi[i]);
  crba_detail::massMatrixFromTransforms(model, data);
  return data.M;
}

}  // namespace dynid
