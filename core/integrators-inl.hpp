#pragma once

#include "core/aba-inl.hpp"
#include "core/integrators.hpp"
#include "core/lanes.hpp"

namespace dynid {

namespace integrators_detail {

/// data.liMi at the stage q_stage, from the step's sines and cosines in data.sin_q, data.cos_q.
/// A revolute joint's stage angle differs from q by a small d = q_stage - q (h/2 dq or h dq), so
/// sin(q + d) = sin q cos d + cos q sin d, with cos d and sin d from their Taylor series: a few
/// multiplications instead of a sin/cos call (RK4's stages 2 to 4). For |d| <= 1e-2 the series,
/// cut after d^5 and d^6, are off by at most d^7 / 7! = 2e-18 and d^8 / 8! = 2.5e-21: absolute
/// errors in the rotation's entries below 2 % of an ulp of 1. A larger d calls sin and cos.
template <typename Scalar>
void stageTransforms(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                     const ConstVectorRef<Scalar>& q, const VectorX<Scalar>& q_stage) {
  using std::abs;
  for (int i = 0; i < model.numJoints(); ++i) {
    if (model.joint_types()[i] == JointType::kPrismatic) {
      setJointTransform(model, i, q_stage[i], data.liMi[i]);
      continue;
    }
    const Scalar d = q_stage[i] - q[i];
    // Lanes (core/lanes.hpp) take the series only when every lane may.
    if (!allLanes(abs(d) <= Scalar(1e-2))) {
      setJointTransform(model, i, q_stage[i], data.liMi[i]);
      continue;
    }
    // Horner form with the coefficients as constants: a division by 6 or 20 is not turned into a
    // multiplication by the compiler, and six divisions per joint were the loop's main cost.
    const Scalar d2 = d * d;
    const Scalar sin_d = d * (Scalar(1) + d2 * (Scalar(-1.0 / 6.0) + d2 * Scalar(1.0 / 120.0)));
    const Scalar cos_d =
        Scalar(1) + d2 * (Scalar(-0.5) + d2 * (Scalar(1.0 / 24.0) + d2 * Scalar(-1.0 / 720.0)));
    setRevoluteTransform(model, i, data.sin_q[i] * cos_d + data.cos_q[i] * sin_d,
                         data.cos_q[i] * cos_d - data.sin_q[i] * sin_d, data.liMi[i]);
  }
}

}  // namespace integrators_detail

template <typename Scalar>
void rk4Step(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data, VectorRef<Scalar> q,
             VectorRef<Scalar> dq, const ConstVectorRef<Scalar>& tau, const Scalar& h) {
  checkState(model, data, q, dq, tau, "tau");
  const Scalar half = h / Scalar(2);
  // k1 = (dq, ddq(q, dq)); the step's sines and cosines kept for the other stages.
  for (int i = 0; i < model.numJoints(); ++i) {
    if (model.joint_types()[i] == JointType::kPrismatic) {
      setJointTransform(model, i, q[i], data.liMi[i]);
      continue;
    }
    // q[i] read once: a store to sin_q could alias q, and a reload would keep the compiler from
    // merging sin and cos into one sincos call.
    const Scalar qi = q[i];
    sinCos(qi, data.sin_q[i], data.cos_q[i]);
    setRevoluteTransform(model, i, data.sin_q[i], data.cos_q[i], data.liMi[i]);
  }
  aba_detail::abaAtTransforms(model, data, dq, tau);
  data.q_increment = dq;
  data.dq_increment = data.ddq;
  data.q_stage = q + half * dq;
  data.dq_stage = dq + half * data.ddq;
  // k2 at (q + h/2 k1)
  integrators_detail::stageTransforms(model, data, q, data.q_stage);
  aba_detail::abaAtTransforms(model, data, data.dq_stage, tau);
  data.q_increment += Scalar(2) * data.dq_stage;
  data.dq_increment += Scalar(2) * data.ddq;
  data.q_stage = q + half * data.dq_stage;
  data.dq_stage = dq + half * data.ddq;
  // k3 at (q + h/2 k2)
  integrators_detail::stageTransforms(model, data, q, data.q_stage);
  aba_detail::abaAtTransforms(model, data, data.dq_stage, tau);
  data.q_increment += Scalar(2) * data.dq_stage;
  data.dq_increment += Scalar(2) * data.ddq;
  data.q_stage = q + h * data.dq_stage;
  data.dq_stage = dq + h * data.ddq;
  // k4 at (q + h k3); x += h/6 (k1 + 2 k2 + 2 k3 + k4)
  integrators_detail::stageTransforms(model, data, q, data.q_stage);
  aba_detail::abaAtTransforms(model, data, data.dq_stage, tau);
  data.q_increment += data.dq_stage;
  data.dq_increment += data.ddq;
  const Scalar sixth = h / Scalar(6);
  q += sixth * data.q_increment;
  dq += sixth * data.dq_increment;
}

template <typename Scalar>
void semiImplicitEulerStep(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                           VectorRef<Scalar> q, VectorRef<Scalar> dq,
                           const ConstVectorRef<Scalar>& tau, const Scalar& h) {
  aba(model, data, q, dq, tau);
  dq += h * data.ddq;
  q += h * dq;
}

}  // namespace dynid
