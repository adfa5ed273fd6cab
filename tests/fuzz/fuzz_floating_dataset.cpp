// libFuzzer target: the floating dataset reader (data/floating/floating_dataset.hpp; the base's
// motion from base: columns or from an IMU), against a one-joint floating robot (base `b`, joint
// `j`, frames `l` and `f`). A dataset it accepts must be written and read back to the same numbers
// (the orientation within a rounding: it is normalised).
#include <cstdint>

#include "core/errors.hpp"
#include "data/floating/floating_dataset.hpp"
#include "data/urdf.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const dynid::FloatingModel model =
      dynid::parseFloatingUrdf(dynid::fuzz::kOneJointFloatingRobot, "r.urdf");
  const std::string path = dynid::fuzz::inputFile(data, size, ".csv");
  dynid::FloatingDataset d;
  try {
    d = dynid::readFloatingDataset(path, model);
  } catch (const dynid::Error&) {
    return 0;
  }
  dynid::writeFloatingDataset(path, d);
  const dynid::FloatingDataset back = dynid::readFloatingDataset(path, model);
  if (back.time != d.time || back.twist != d.twist || back.acceleration != d.acceleration ||
      back.q != d.q || back.dq != d.dq || back.ddq != d.ddq || back.tau != d.tau ||
      back.wrenches.size() != d.wrenches.size() || back.flags.size() != d.flags.size() ||
      (back.orientation - d.orientation).cwiseAbs().maxCoeff() > 1e-15)
    __builtin_trap();
  for (std::size_t k = 0; k < d.wrenches.size(); ++k)
    if (back.wrenches[k].frame != d.wrenches[k].frame ||
        back.wrenches[k].values != d.wrenches[k].values)
      __builtin_trap();
  for (std::size_t k = 0; k < d.flags.size(); ++k)
    if (back.flags[k].frame != d.flags[k].frame || back.flags[k].holding != d.flags[k].holding)
      __builtin_trap();
  return 0;
}
