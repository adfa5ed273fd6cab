// libFuzzer target: search checkpoints (analysis/records/, checkpointFrom), against the shape
// of a GA run on the PUMA's 42 paper parameters with a population of 6.
#include <cstdint>

#include "analysis/records/document.hpp"
#include "analysis/records/search_record.hpp"
#include "core/errors.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const nlohmann::json doc = dynid::parseJson(dynid::fuzz::text(data, size), "ga.ckpt");
    const dynid::SearchState state = dynid::checkpointFrom(doc, "ga.ckpt", {"ga", 42, 6});
    if (state.best_x.size() != 42) __builtin_trap();
  } catch (const dynid::Error&) {
  }
  return 0;
}
