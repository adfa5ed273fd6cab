// A floating dataset as the recording the GC error on a floating base rolls out
// (search/floating/floating_gc.hpp; docs/FLOATING.md, "The GC error on a floating base").
#pragma once

#include <string>
#include <vector>

#include "data/floating/floating_dataset.hpp"
#include "search/floating/floating_gc.hpp"

namespace dynid {

/// The dataset's time, base orientation and twist, q, dq, joint torques and, for each of
/// `contacts` (resolved against the model: a frame contact reads six wrench components, a point
/// three), its measured wrench, or its flag where it has no wrench of its dimension (the rollout
/// then holds it still in the world while it holds: FloatingGcData::flags). Throws InputError
/// naming the file when the dataset measures no joint torques or a contact has neither. The base's
/// linear velocity is taken as unrecorded (FloatingGcData::linear_velocity false) when the base
/// motion came from an IMU, or when it is zero in every sample while the base's linear acceleration
/// is not (a prepared IMU recording written out: a base that accelerates never stays still).
FloatingGcData floatingGcData(const FloatingDataset& dataset, const std::vector<Contact>& contacts);

/// The same with the contacts by name (contactsOf's specifications, "F" a point, "F:frame" a
/// frame); none: every frame the dataset measures a wrench at (a frame contact for six components,
/// a point for three), and every frame it flags without a wrench (a point).
FloatingGcData floatingGcData(const FloatingModel& model, const FloatingDataset& dataset,
                              const std::vector<std::string>& contacts);

/// Why the dataset's samples are not one recorded motion a rollout can follow (empty: they are):
/// between consecutive samples less than 1.5 median periods apart, the joints' step
/// q(k+1) - q(k) and the trapezoid of dq over it, (t(k+1) - t(k)) (dq(k) + dq(k+1)) / 2, differ
/// (largest joint) by more than half the larger of the two (medians over the steps) and by more
/// than kMotionStepTolerance: independent states (a simulation's random ones) step by what dq
/// does not explain. A robot with no joint is taken as a motion.
std::string floatingMotionRefusal(const FloatingDataset& dataset);

/// The step mismatch [rad] below which samples count as a motion whatever their steps: joints at
/// rest step by their encoders' noise, far below it (1e-5 rad for a 16-bit encoder).
inline constexpr double kMotionStepTolerance = 1e-3;

}  // namespace dynid
