// summary.json read back: a least-squares summary of one robot's logs (dynid summarize; the
// Python module's Summary), what an identify request's `summary`, a merge and the Python
// module's pickling read. Written by reports/summary_report.hpp.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/records/model_source.hpp"
#include "core/model.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares_summary.hpp"
#include "identifiability/rows/fit_rows.hpp"

namespace dynid {

/// How a summary's factors are written: each batch's joints' upper triangles, row by row, as
/// base64 of their IEEE 754 binary64 values, little-endian (data/digest/base64.hpp).
inline constexpr const char* kSummaryEncoding =
    "base64 of little-endian IEEE 754 binary64: each joint's upper triangle, row by row";

/// One log a summary holds.
struct SummarySource {
  std::string file;    // as given (empty: data in memory)
  std::string sha256;  // its content's (empty: data in memory)
  long long samples = 0;
  std::vector<double> rest_velocity;  // per joint, as the fit took them [rad/s or m/s]
  TorqueFilter torque_filter;         // the filter the rows reproduce (inactive: none)
  std::string torque_filter_source;   // where it came from, or why there is none
};

/// A least-squares summary of one robot's logs: the robot it was made for (the base parameters
/// follow from its structure and `structural`), the factors, and the logs.
struct Summary {
  Model model;  // structure, drive terms and the parameters as given (the prior of what's unseen)
  ModelSource model_source;
  StructuralOptions structural;
  std::vector<std::string> base_names;  // the base parameters, in the factors' column order
  LeastSquaresSummary factors;
  std::vector<SummarySource> sources;
};

/// The summary in `document` (`file` names it in messages): kind dynid.summary, version 1,
/// every field checked (the factors' sizes against the supports, the model's joints against the
/// supports' count). Throws ParseError naming the file and the field. With `detached`, the
/// batches' values are there, in order (summaryJson's detached form: each batch's "factors" "").
Summary summaryFrom(const nlohmann::json& document, const std::string& file,
                    const std::vector<double>* detached = nullptr);
/// The same from a file (read through data/io's readFile: a command's input).
Summary readSummary(const std::string& file);

}  // namespace dynid
