// libFuzzer target: the dataset CSV reader (data/dataset_csv.hpp). A dataset it accepts must be
// written and read back to the same numbers.
#include <cstdint>

#include "core/errors.hpp"
#include "data/dataset_csv.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = dynid::fuzz::inputFile(data, size, ".csv");
  dynid::Trajectory t;
  try {
    t = dynid::readDatasetCsv(path);
  } catch (const dynid::Error&) {
    return 0;
  }
  dynid::writeDatasetCsv(path, t);
  const dynid::Trajectory back = dynid::readDatasetCsv(path);
  if (back.time != t.time || back.q != t.q || back.dq != t.dq || back.ddq != t.ddq ||
      back.tau != t.tau)
    __builtin_trap();
  return 0;
}
