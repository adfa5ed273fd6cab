// Mechanical energy, for checking integrators and for users' own diagnostics.
#pragma once

#include "core/data.hpp"

namespace dynid {

/// Kinetic energy 1/2 dq^T M(q) dq [J] (rotor inertia included when drives are enabled).
/// q, dq have n entries. Overwrites data.liMi, data.v.
double kineticEnergy(const Model& model, Data& data, const ConstVectorRef<double>& q,
                     const ConstVectorRef<double>& dq);

/// Potential energy -sum_i m_i g . c_i [J] in the base frame (zero at the base origin).
/// q has n entries. Overwrites data.liMi, data.oMi.
double potentialEnergy(const Model& model, Data& data, const ConstVectorRef<double>& q);

}  // namespace dynid
