#include "analysis/floating/identifiability.hpp"

#include <algorithm>

#include "core/errors.hpp"

namespace dynid {

std::vector<Contact> contactsOf(const FloatingModel& model, const std::vector<std::string>& specs) {
  std::vector<Contact> out;
  for (const std::string& spec : specs) {
    Contact contact;
    std::string name = spec;
    if (const std::size_t colon = spec.rfind(':'); colon != std::string::npos) {
      name = spec.substr(0, colon);
      const std::string kind = spec.substr(colon + 1);
      if (kind == "frame")
        contact.kind = Contact::Kind::kFrame;
      else if (kind != "point")
        throw InputError("`contacts`: '" + spec + "' ends in ':" + kind +
                         "'; a contact is NAME, NAME:point (a force) or NAME:frame (a wrench)");
    }
    const BodyFrame* frame = model.findFrame(name);
    if (frame == nullptr) {
      std::string names;
      for (const BodyFrame& f : model.frames)
        if (f.body >= 0) names += (names.empty() ? "" : ", ") + f.name;
      throw InputError("`contacts`: '" + name + "' is no link of '" + model.name() +
                       "'; its links below the base: " + names);
    }
    for (const Contact& c : out)
      if (c.name == name) throw InputError("`contacts` names '" + name + "' twice");
    contact.name = name;
    contact.body = frame->body;
    contact.placement = frame->placement;
    out.push_back(contact);
  }
  return out;
}

FloatingIdentifiabilityOutcome floatingIdentifiabilityRun(
    const FloatingModel& model, const FloatingIdentifiabilityRequest& request) {
  request.check();
  FloatingIdentifiabilityOutcome out;
  out.contacts = contactsOf(model, request.contacts);
  out.motion = request.motion.value_or(out.contacts.empty() ? FloatingMotion::kFree
                                                            : FloatingMotion::kHolding);
  out.structural = request.structural;
  // By default every set, but wrenches in flight (nothing carries one).
  std::vector<SensorSet> sets = request.sensors;
  if (sets.empty())
    for (SensorSet set : kSensorSets)
      if (set != SensorSet::kWrenches || out.motion != FloatingMotion::kFree) sets.push_back(set);
  FloatingStructuralOptions options{request.structural, out.contacts, out.motion};
  out.sets = floatingStructuralBase(model, sets, options);
  const Eigen::VectorXd theta = model.standardParameters();
  for (const SensorSetBase& s : out.sets) out.model_beta.push_back(s.base.project(theta));
  const auto find = [&](SensorSet set) -> const SensorSetBase* {
    for (const SensorSetBase& s : out.sets)
      if (s.set == set) return &s;
    return nullptr;
  };
  const SensorSetBase* full = find(SensorSet::kTorquesAndWrenches);
  if (full != nullptr)
    for (SensorSet from : {SensorSet::kWrenches, SensorSet::kTorquesAndContactFlags})
      if (const SensorSetBase* s = find(from))
        out.gains.push_back(
            {from, SensorSet::kTorquesAndWrenches, full->base.numBase() - s->base.numBase()});
  return out;
}

}  // namespace dynid
