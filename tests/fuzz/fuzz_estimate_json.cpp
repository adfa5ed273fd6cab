// libFuzzer target: an identify estimate.json as predict and refine read it
// (analysis/records/, estimateRecordFrom and standardVectorFrom) for the built-in PUMA 560.
#include <cstdint>

#include "analysis/records/document.hpp"
#include "analysis/records/estimate_record.hpp"
#include "core/errors.hpp"
#include "core/parameters.hpp"
#include "data/puma560.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::vector<std::string> names =
      dynid::standardParameterNames(dynid::makePuma560().parameterLayout());
  try {
    const nlohmann::json doc = dynid::parseJson(dynid::fuzz::text(data, size), "estimate.json");
    const dynid::EstimateRecord record = dynid::estimateRecordFrom(doc, "estimate.json");
    const Eigen::VectorXd theta =
        dynid::standardVectorFrom(record, names, "estimate.json", "puma560");
    if (theta.size() != static_cast<Eigen::Index>(names.size()) || !theta.allFinite())
      __builtin_trap();
  } catch (const dynid::Error&) {
  }
  return 0;
}
