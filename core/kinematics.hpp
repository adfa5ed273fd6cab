// Forward kinematics: the placement of every body.
#pragma once

#include "core/data.hpp"

namespace dynid {

/// Places every body at joint positions q (n entries, rad or m): data.oMi[i] is link frame i (the
/// frame of its parameters) in the base frame; data.oMj and data.liMi hold the joint frames
/// (data.hpp). Throws InputError on a size mismatch. Overwrites data.liMi, data.oMj, data.oMi.
/// Returns data.oMi.
template <typename Scalar>
const std::vector<Pose<Scalar>>& forwardKinematics(const ModelTpl<Scalar>& model,
                                                   DataTpl<Scalar>& data,
                                                   const ConstVectorRef<Scalar>& q);

extern template const std::vector<Pose<double>>& forwardKinematics(const Model&, Data&,
                                                                   const ConstVectorRef<double>&);

}  // namespace dynid
