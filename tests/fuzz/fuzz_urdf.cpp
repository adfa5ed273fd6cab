// libFuzzer target: the URDF loader (data/urdf.hpp), urdfdom and its XML parser underneath. A
// robot it accepts must export to URDF and load back with the same joint count.
#include <cstdint>

#include "core/errors.hpp"
#include "data/urdf.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dynid::Model model;
  try {
    model = dynid::parseUrdf(dynid::fuzz::text(data, size), "fuzz.urdf");
  } catch (const dynid::Error&) {
    return 0;
  }
  const dynid::Model back = dynid::parseUrdf(dynid::modelToUrdf(model), "export.urdf");
  if (back.numJoints() != model.numJoints()) __builtin_trap();
  return 0;
}
