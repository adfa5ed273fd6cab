// libFuzzer target: a summary.json as identify --summaries reads it (analysis/records/
// summaryFrom, then the base parameters it claims and its estimate): no crash, no hang, every
// refusal an Error.
#include <cstdint>

#include "analysis/records/document.hpp"
#include "analysis/runs/summarize.hpp"
#include "core/errors.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const nlohmann::json doc = dynid::parseJson(dynid::fuzz::text(data, size), "summary.json");
    const dynid::Summary summary = dynid::summaryFrom(doc, "summary.json");
    if (summary.model.numJoints() > 8) return 0;  // the base parameters' cost, not the reader's
    const dynid::BaseParameters base = dynid::summaryBase(summary, "summary.json");
    dynid::LeastSquaresStream stream(base, summary.model);
    summary.factors.addTo(stream);
    const dynid::BaseEstimate e = stream.estimate(dynid::LeastSquaresMethod::kWeighted);
    if (e.beta.size() != base.numBase()) __builtin_trap();
  } catch (const dynid::Error&) {
  }
  return 0;
}
