// The worker processes of `dynid batch`: each run of a plan is this executable started as
// `dynid batch run --spec JSON --out FILE` (command_batch.cpp), so a run that crashes or is
// killed costs only itself. The library plans and collects (analysis/studies/batch.hpp); this is
// the front end's process pool.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>

#include "analysis/studies/batch.hpp"

namespace dynid::cli {

/// A worker that exited: how many have (of how many to run), its run's index in plan.runs, and
/// whether it succeeded (exit 0).
struct FinishedRun {
  std::size_t finished, todo, run;
  bool ok;
};

/// Runs plan.todo in worker processes of this executable (/proc/self/exe), `jobs` at a time;
/// stops starting runs when *stop is set. `on_finished` after each worker exits.
/// Returns collectBatch(plan) with the failed runs (a worker that did not exit 0, unless
/// stopped) and whether it was interrupted. Throws InputError when the executable cannot be
/// found.
BatchOutcome runBatchWorkers(const BatchPlan& plan, int jobs, const std::atomic<bool>* stop,
                             const std::function<void(const FinishedRun&)>& on_finished = {});

}  // namespace dynid::cli
