// libFuzzer target: the MCAP reader (data/bags/mcap.hpp) and the message decoders
// (data/bags/ros_messages.hpp: JointState, Imu, WrenchStamped, Bool) on every message it hands
// over, as both CDR and ROS 1.
#include <cstdint>

#include "core/errors.hpp"
#include "data/bags/mcap.hpp"
#include "data/bags/ros_messages.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = dynid::fuzz::inputFile(data, size, ".mcap");
  try {
    dynid::bags::McapReader reader(path);
    reader.read([&](const dynid::bags::McapMessage& m) {
      if (m.data.size() > size) __builtin_trap();  // a message larger than the file
      dynid::bags::JointStateMessage js;
      for (bool cdr : {true, false}) {
        try {
          if (cdr)
            dynid::bags::decodeJointStateCdr(m.data, path, m.offset, js);
          else
            dynid::bags::decodeJointStateRos1(m.data, path, m.offset, js);
          // Every array the decoder made came from the message's bytes: 8 per double.
          if (8 * (js.position.size() + js.velocity.size() + js.effort.size()) > m.data.size())
            __builtin_trap();
        } catch (const dynid::Error&) {
        }
        // The floating base's messages: fixed-size fields, a frame_id within the bytes.
        dynid::bags::ImuMessage imu;
        dynid::bags::WrenchStampedMessage wrench;
        try {
          (cdr ? dynid::bags::decodeImuCdr : dynid::bags::decodeImuRos1)(m.data, path, m.offset,
                                                                         imu);
        } catch (const dynid::Error&) {
        }
        try {
          (cdr ? dynid::bags::decodeWrenchStampedCdr : dynid::bags::decodeWrenchStampedRos1)(
              m.data, path, m.offset, wrench);
        } catch (const dynid::Error&) {
        }
        if (imu.frame_id.size() > m.data.size() || wrench.frame_id.size() > m.data.size())
          __builtin_trap();
        try {
          (cdr ? dynid::bags::decodeBoolCdr : dynid::bags::decodeBoolRos1)(m.data, path, m.offset);
        } catch (const dynid::Error&) {
        }
      }
    });
  } catch (const dynid::Error&) {
  }
  return 0;
}
