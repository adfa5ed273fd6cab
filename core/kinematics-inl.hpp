#pragma once

#include "core/checks.hpp"
#include "core/kinematics.hpp"

namespace dynid {

template <typename Scalar>
const std::vector<Pose<Scalar>>& forwardKinematics(const ModelTpl<Scalar>& model,
                                                   DataTpl<Scalar>& data,
                                                   const ConstVectorRef<Scalar>& q) {
  checkData(model, data);
  checkSize(model, q, "q");
  for (int i = 0; i < model.numJoints(); ++i) {
    // oMj_i = oMj_parent liMi;  oMi = oMj_i body_placement_i
    setJointTransform(model, i, q[i], data.liMi[i]);
    const int p = model.parents()[i];
    data.oMj[i] = p < 0 ? data.liMi[i] : data.oMj[p] * data.liMi[i];
    data.oMi[i] = data.oMj[i] * model.body_placements()[i];
  }
  return data.oMi;
}

}  // namespace dynid
