// Forward kinematics: the placement of every body.
#pragma once

#include "core/data.hpp"

namespace dynid {

/// Computes data.liMi (body i in its parent's frame) and data.oMi (body i in the base frame) at
/// joint positions q (n entries, rad or m). Throws InputError on a size mismatch. Overwrites
/// data.liMi, data.oMi. Returns data.oMi.
template <typename Scalar>
const std::vector<Pose<Scalar>>& forwardKinematics(const ModelTpl<Scalar>& model,
                                                   DataTpl<Scalar>& data,
                                                   const ConstVectorRef<Scalar>& q);

extern template const std::vector<Pose<double>>& forwardKinematics(const Model&, Data&,
                                                                   const ConstVectorRef<double>&);

}  // namespace dynid
