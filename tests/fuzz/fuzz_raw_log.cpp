// libFuzzer target: the raw log readers of `dynid prepare` (analysis/logs/raw_log.hpp): a table's
// header, its columns, glob selectors, and one-signal-per-file logs.
#include <cstdint>

#include "analysis/logs/raw_log.hpp"
#include "core/errors.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The first byte picks the value file's width (1 to 8); the rest is the file.
  if (size == 0) return 0;
  const int width = 1 + data[0] % 8;
  const std::string path = dynid::fuzz::inputFile(data + 1, size - 1, ".log");
  try {
    const dynid::RawTable header = dynid::readRawHeader(path);
    std::vector<int> all;
    for (std::size_t c = 0; c < header.names.size(); ++c) all.push_back(static_cast<int>(c));
    const Eigen::MatrixXd values = dynid::readRawColumns(header, all);
    if (values.cols() != static_cast<Eigen::Index>(all.size()) || !values.allFinite())
      __builtin_trap();
    for (const char* selector : {"q*", "1,2", "tau?", "*"}) {
      try {
        dynid::selectColumns(header, selector, -1, "--q");
      } catch (const dynid::Error&) {
      }
    }
  } catch (const dynid::Error&) {
  }
  try {
    const Eigen::MatrixXd values = dynid::readValueFile(path, width);
    if (values.cols() != width || !values.allFinite()) __builtin_trap();
  } catch (const dynid::Error&) {
  }
  return 0;
}
