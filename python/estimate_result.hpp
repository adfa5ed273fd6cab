// What the runs wing's Python bindings share: identify()'s result (the Estimate class), which
// predict() takes for its band, and the deprecation warning of the fraction-valued relative_error.
#pragma once

#include "analysis/records/provenance.hpp"
#include "analysis/runs/identify.hpp"
#include "core/model.hpp"
#include "python/common.hpp"

namespace dynid::python {

/// What `identify()` returns.
struct EstimateResult {
  Model model;  // the robot as given (its parameters are the prior)
  IdentifyOutcome outcome;
  RunProvenance provenance;  // the call that made it (to_json's provenance)
};

/// relative_error is a fraction where the CLI prints percent: it warns, naming the property that
/// carries its unit. (A DeprecationWarning: shown in tests and __main__, silent elsewhere.)
inline void warnFraction() {
  if (PyErr_WarnEx(PyExc_DeprecationWarning,
                   "relative_error is the fraction ||tau - tau_hat|| / ||tau||; "
                   "relative_error_percent is the same in percent, as the CLI prints it",
                   1) != 0)
    throw py::error_already_set();
}

}  // namespace dynid::python
