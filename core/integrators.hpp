// Fixed-step integrators of the forward dynamics, with the joint torque held constant over the step
// (zero-order hold). The state is (q, dq); q is a plain vector (revolute and prismatic joints
// only).
#pragma once

#include <string>

#include "core/data.hpp"

namespace dynid {

enum class IntegratorType { kRk4, kSemiImplicitEuler };

/// "rk4" or "euler" (semi-implicit Euler).
const char* integratorName(IntegratorType type);
/// Parses "rk4" or "euler"; throws InputError otherwise.
IntegratorType parseIntegrator(const std::string& name);

/// Classical 4th-order Runge-Kutta step of length h [s]: four forward-dynamics evaluations.
/// q, dq (n entries) are advanced in place; tau (n entries) is held over the step.
/// Overwrites the ABA fields of data and data.q_stage, dq_stage, q_increment, dq_increment, sin_q,
/// cos_q (stages 2-4 form their joint transforms from sin q and cos q by angle addition).
/// Allocates nothing. tau must not alias data's buffers.
template <typename Scalar>
void rk4Step(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data, VectorRef<Scalar> q,
             VectorRef<Scalar> dq, const ConstVectorRef<Scalar>& tau, const Scalar& h);

/// Semi-implicit (symplectic) Euler step: dq += h ddq(q, dq, tau); q += h dq. One forward-dynamics
/// evaluation. Same contract as rk4Step.
template <typename Scalar>
void semiImplicitEulerStep(const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                           VectorRef<Scalar> q, VectorRef<Scalar> dq,
                           const ConstVectorRef<Scalar>& tau, const Scalar& h);

/// One step of the chosen integrator.
template <typename Scalar>
void integratorStep(IntegratorType type, const ModelTpl<Scalar>& model, DataTpl<Scalar>& data,
                    VectorRef<Scalar> q, VectorRef<Scalar> dq, const ConstVectorRef<Scalar>& tau,
                    const Scalar& h) {
  if (type == IntegratorType::kRk4)
    rk4Step(model, data, q, dq, tau, h);
  else
    semiImplicitEulerStep(model, data, q, dq, tau, h);
}

extern template void rk4Step(const Model&, Data&, VectorRef<double>, VectorRef<double>,
                             const ConstVectorRef<double>&, const double&);
extern template void semiImplicitEulerStep(const Model&, Data&, VectorRef<double>,
                                           VectorRef<double>, const ConstVectorRef<double>&,
                                           const double&);

}  // namespace dynid
