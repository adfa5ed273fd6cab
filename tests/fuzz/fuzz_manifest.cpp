// libFuzzer target: batch manifests (analysis/studies/batch.hpp): parsing, the grid's expansion and
// every run's settings.
#include <cstdint>

#include "analysis/records/document.hpp"
#include "analysis/studies/batch.hpp"
#include "core/errors.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const nlohmann::json manifest = dynid::parseJson(dynid::fuzz::text(data, size), "m.json");
    for (const nlohmann::json& run : dynid::expandManifest(manifest, "m.json")) {
      try {
        dynid::studySettingsOf(run).check();
      } catch (const dynid::InputError&) {
      }
    }
  } catch (const dynid::Error&) {
  }
  return 0;
}
