// The floating wing (analysis/floating/, floor 3): floating-base robots' command family. This room:
// what each sensor set determines (`dynid identifiability --floating-base`, docs/FLOATING.md).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/floating/contact_jacobian.hpp"
#include "identifiability/floating/sensor_sets.hpp"

namespace dynid {

struct FloatingIdentifiabilityRequest {
  /// The contacts, each a frame of the model (a URDF link) by name, optionally followed by
  /// ":point" (a force through its origin, the default) or ":frame" (a wrench: a flat foot).
  std::vector<std::string> contacts;
  /// The sensor sets to analyse; empty: all three.
  std::vector<SensorSet> sensors;
  /// The motion of the data the analysis is for; holding needs contacts. Unset: holding when
  /// there are contacts, free (in flight) when there are none.
  std::optional<FloatingMotion> motion;
  StructuralOptions structural;
  /// Throws InputError naming the field out of its range (structural's).
  void check() const { structural.check(); }
};

/// What one added sensor brings: the count of base parameters `to` determines beyond `from`
/// (from's rows lie in to's).
struct SensorGain {
  SensorSet from, to;
  int gained = 0;
};

struct FloatingIdentifiabilityOutcome {
  std::vector<Contact> contacts;
  FloatingMotion motion = FloatingMotion::kHolding;
  StructuralOptions structural;
  std::vector<SensorSetBase> sets;
  std::vector<SensorGain> gains;
  /// The model's own base parameters, per set (set order).
  std::vector<Eigen::VectorXd> model_beta;
};

/// The contacts of `specs` (FloatingIdentifiabilityRequest::contacts' form) on the model's frames.
/// Throws InputError naming `contacts`, the spec and the frames there are.
std::vector<Contact> contactsOf(const FloatingModel& model, const std::vector<std::string>& specs);

/// Every requested sensor set's structural base parameters on the same states, and what the
/// joint torques add to the wrenches and the wrenches to the contact flags. Throws InputError for
/// a bad request, unknown contacts or holding without contacts.
FloatingIdentifiabilityOutcome floatingIdentifiabilityRun(
    const FloatingModel& model, const FloatingIdentifiabilityRequest& request);

}  // namespace dynid
