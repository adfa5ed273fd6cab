// The floating identifiability run: contacts by frame name, the motion a request leaves unset,
// and the sets it analyses by default.
#include <gtest/gtest.h>

#include "analysis/floating/identifiability.hpp"
#include "data/urdf.hpp"

namespace dynid {
namespace {

FloatingModel anymal() {
  return loadFloatingUrdf(std::string(DYNID_SOURCE_DIR) +
                          "/examples/floating/anymal_c/anymal.urdf");
}

TEST(FloatingContacts, AreFramesByNameWithTheirKind) {
  const FloatingModel model = anymal();
  const std::vector<Contact> contacts = contactsOf(model, {"LF_FOOT", "RH_FOOT:frame", "base"});
  ASSERT_EQ(contacts.size(), 3u);
  EXPECT_EQ(contacts[0].kind, Contact::Kind::kPoint);
  EXPECT_EQ(contacts[1].kind, Contact::Kind::kFrame);
  EXPECT_EQ(contacts[2].body, -1);  // the base's own frame (a support under the trunk)
  EXPECT_EQ(contacts[0].body, model.findFrame("LF_FOOT")->body);
  EXPECT_TRUE(contacts[0].placement.translation.isApprox(
      model.findFrame("LF_FOOT")->placement.translation));
  EXPECT_THROW(contactsOf(model, {"LF_FOOT:sphere"}), InputError);
  EXPECT_THROW(contactsOf(model, {"LF_FOOT", "LF_FOOT:frame"}), InputError);
  EXPECT_THROW(contactsOf(model, {"LF_PAW"}), InputError);
}

TEST(FloatingIdentifiabilityRun, AnUnsetMotionHoldsContactsOrFlies) {
  const FloatingModel model = anymal();
  FloatingIdentifiabilityRequest request;
  request.contacts = {"LF_FOOT", "RF_FOOT", "LH_FOOT", "RH_FOOT"};
  request.structural.samples = 60;
  const FloatingIdentifiabilityOutcome standing = floatingIdentifiabilityRun(model, request);
  EXPECT_EQ(standing.motion, FloatingMotion::kHolding);
  EXPECT_EQ(standing.sets.size(), 3u);
  request.contacts.clear();
  const FloatingIdentifiabilityOutcome flying = floatingIdentifiabilityRun(model, request);
  EXPECT_EQ(flying.motion, FloatingMotion::kFree);
  // In flight nothing carries a wrench: the default leaves that set out.
  ASSERT_EQ(flying.sets.size(), 2u);
  EXPECT_EQ(flying.sets[0].set, SensorSet::kTorquesAndWrenches);
  // Asked for it, it is refused.
  request.sensors = {SensorSet::kWrenches};
  EXPECT_THROW(floatingIdentifiabilityRun(model, request), InputError);
}

}  // namespace
}  // namespace dynid
