// libFuzzer target: the search.json or estimate.json a refinement starts from
// (analysis/records/, refineStartFrom), on the built-in PUMA 560.
#include <cstdint>

#include "analysis/records/document.hpp"
#include "analysis/records/estimate_record.hpp"
#include "core/errors.hpp"
#include "data/puma560.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const dynid::Model puma = dynid::makePuma560();
  try {
    const nlohmann::json doc = dynid::parseJson(dynid::fuzz::text(data, size), "search.json");
    dynid::refineStartFrom(doc, "search.json", puma, {}, {});
  } catch (const dynid::Error&) {
  }
  return 0;
}
