// What the runs wing's Python bindings share of summaries: summarize()'s result (the Summary
// class), which identify() takes as its data.
#pragma once

#include "analysis/records/provenance.hpp"
#include "analysis/records/summary_record.hpp"
#include "python/common.hpp"

namespace dynid::python {

/// What `summarize()` returns, and what `+` and `Summary.load` make.
struct SummaryResult {
  Summary summary;
  RunProvenance provenance;  // the call that made it (to_json's); empty for a merge or a load
};

}  // namespace dynid::python
