// Seeded perturbations of a model's parameters: the paper's "initial guess" and imperfect
// controller models.
#pragma once

#include <cstdint>

#include "core/model.hpp"

namespace dynid {

/// A copy of `model` whose paper-form parameters (m, c, principal inertia about the centre of mass,
/// per link) and drive parameters are each multiplied by (1 + u), u uniform in [-fraction,
/// fraction], drawn from std::mt19937_64(seed) in parameter order. Zero parameters stay zero.
/// Products of inertia about the centre of mass are kept. Throws InputError unless
/// 0 <= fraction < 1.
Model perturbedModel(const Model& model, double fraction, std::uint64_t seed);

}  // namespace dynid
