// libFuzzer target: the raw floating log reader (data/floating/floating_log.hpp) and the
// preparation behind it (analysis/floating/prepare.hpp: resampling, gaps, filter, derivatives),
// against a one-joint floating robot (base `b`, joint `j`, frames `l` and `f`). What the reader
// accepts holds `width` values per sample at increasing lines; what the preparation makes is
// finite, its time increasing.
#include <cmath>
#include <cstdint>

#include "analysis/floating/prepare.hpp"
#include "core/errors.hpp"
#include "data/floating/floating_log.hpp"
#include "data/urdf.hpp"
#include "tests/fuzz/fuzz_input.hpp"

namespace {

void check(const dynid::FloatingLogSignal& s) {
  if (s.values.size() != static_cast<std::size_t>(s.width) * s.time.size() ||
      s.lines.size() != s.time.size())
    __builtin_trap();
  for (std::size_t k = 1; k < s.lines.size(); ++k)
    if (s.lines[k] <= s.lines[k - 1]) __builtin_trap();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const dynid::FloatingModel model =
      dynid::parseFloatingUrdf(dynid::fuzz::kOneJointFloatingRobot, "r.urdf");
  const std::string path = dynid::fuzz::inputFile(data, size, ".csv");
  try {
    const dynid::FloatingLogTable table = dynid::readFloatingLogTable(path, model);
    check(table.joints);
    check(table.imu);
    for (const auto& w : table.wrenches) check(w);
    for (const auto& f : table.flags) check(f);
  } catch (const dynid::Error&) {
    return 0;
  }
  try {
    const dynid::FloatingDataset d = dynid::prepareFloatingLog(model, path, {}, {}).dataset;
    for (int k = 0; k < d.numSamples(); ++k) {
      if (k > 0 && !(d.time[k] > d.time[k - 1])) __builtin_trap();
      if (!d.q.col(k).allFinite() || !d.ddq.col(k).allFinite() ||
          !d.acceleration.col(k).allFinite() || !d.orientation.col(k).allFinite())
        __builtin_trap();
    }
  } catch (const dynid::Error&) {
  }
  return 0;
}
