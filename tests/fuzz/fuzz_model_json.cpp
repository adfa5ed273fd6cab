// libFuzzer target: dynid JSON models (data/model_json.hpp). A model it accepts must export and
// load back with the same parameters.
#include <cstdint>

#include "core/errors.hpp"
#include "data/model_json.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dynid::Model model;
  try {
    model = dynid::modelFromJson(dynid::fuzz::text(data, size), "fuzz.json");
  } catch (const dynid::Error&) {
    return 0;
  }
  const dynid::Model back = dynid::modelFromJson(dynid::modelToJson(model), "export.json");
  if (back.numJoints() != model.numJoints() ||
      back.standardParameters() != model.standardParameters())
    __builtin_trap();
  return 0;
}
