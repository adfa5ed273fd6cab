// libFuzzer target: a fleet manifest as dynid fleet --manifest reads it (analysis/records/
// fleetManifestFrom): no crash, no hang, every refusal an Error, every robot read with a name and
// exactly one non-empty list of paths.
#include <cstdint>

#include "analysis/records/fleet_manifest.hpp"
#include "core/errors.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    for (const dynid::FleetManifestRobot& r :
         dynid::fleetManifestFrom(dynid::fuzz::text(data, size), "dir/fleet.json"))
      if (r.name.empty() || r.data.empty() == r.summaries.empty()) __builtin_trap();
  } catch (const dynid::Error&) {
  }
  return 0;
}
