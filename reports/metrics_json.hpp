// A comparison row as JSON, shared by summary.json (dynid demo) and the batch results.
#pragma once

#include <nlohmann/json.hpp>

#include "analysis/comparison.hpp"

namespace dynid {

/// {gc_error_initial, gc_error_train, gc_error_test, torque_rms_test, param_error,
/// base_param_error, evaluations, seconds}; non-finite numbers are null.
nlohmann::json metricsJson(const MethodMetrics& m);

}  // namespace dynid
