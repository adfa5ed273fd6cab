#pragma once

#include "core/aba-inl.hpp"
#include "core/integrators.hpp"

namespace dynid {

template <typename Scalar>
void rk4Step(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data, VectorRef<Scalar> q,
             VectorRef<Scalar> dq, const ConstVectorRef<Scalar>& tau, const Scalar& h) {
  const Scalar half = h / Scalar(2);
  // k1 = (dq, ddq(q, dq))
  aba(model, data, q, dq, tau);
  data.q_increment = dq;
  data.dq_increment = data.ddq;
  data.q_stage = q + half * dq;
  data.dq_stage = dq + half * data.ddq;
  // k2 at (q + h/2 k1)
  aba(model, data, data.q_stage, data.dq_stage, tau);
  data.q_increment += Scalar(2) * data.dq_stage;
  data.dq_increment += Scalar(2) * data.ddq;
  data.q_stage = q + half * data.dq_stage;
  data.dq_stage = dq + half * data.ddq;
  // k3 at (q + h/2 k2)
  aba(model, data, data.q_stage, data.dq_stage, tau);
  data.q_increment += Scalar(2) * data.dq_stage;
  data.dq_increment += Scalar(2) * data.ddq;
  data.q_stage = q + h * data.dq_stage;
  data.dq_stage = dq + h * data.ddq;
  // k4 at (q + h k3); x += h/6 (k1 + 2 k2 + 2 k3 + k4)
  aba(model, data, data.q_stage, data.dq_stage, tau);
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
