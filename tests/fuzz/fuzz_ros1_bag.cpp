// libFuzzer target: the ROS 1 bag reader (data/bags/ros1_bag.hpp) and the JointState decoders on
// every message it hands over. Seeds: bags written by ROS's own writer.
#include <cstdint>

#include "core/errors.hpp"
#include "data/bags/ros1_bag.hpp"
#include "data/bags/ros_messages.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = dynid::fuzz::inputFile(data, size, ".bag");
  std::size_t total = 0;
  try {
    dynid::bags::readRos1Bag(path, {}, [&](const dynid::bags::BagMessage& m) {
      total += m.data.size();
      dynid::bags::JointStateMessage js;
      try {
        dynid::bags::decodeJointStateRos1(m.data, path, m.offset, js);
        if (8 * (js.position.size() + js.velocity.size() + js.effort.size()) > m.data.size())
          __builtin_trap();  // values the message's bytes cannot hold
      } catch (const dynid::Error&) {
      }
    });
  } catch (const dynid::Error&) {
  }
  // Chunks decompress to at most their stated sizes, each bounded: the messages' bytes cannot
  // exceed what bz2 or lz4 could expand this input to (a generous bound: 1000 times, 64 MiB).
  if (total > 1000 * size + (std::size_t{64} << 20)) __builtin_trap();
  return 0;
}
