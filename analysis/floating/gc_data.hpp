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
/// three), its measured wrench. Throws InputError naming the file when the dataset measures no
/// joint torques or a contact has no wrench of its dimension (a contact known by its flag alone
/// holds by forces no measurement gives: it cannot be rolled out).
FloatingGcData floatingGcData(const FloatingDataset& dataset, const std::vector<Contact>& contacts);

/// The same with the contacts by name (contactsOf's specifications, "F" a point, "F:frame" a
/// frame); none: every frame the dataset measures a wrench at (a frame contact for six components,
/// a point for three).
FloatingGcData floatingGcData(const FloatingModel& model, const FloatingDataset& dataset,
                              const std::vector<std::string>& contacts);

}  // namespace dynid
