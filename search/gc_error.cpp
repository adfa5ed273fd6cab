#include "search/gc_error.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "search/gc_rollout.hpp"

namespace dynid {

namespace {
std::string formatCount(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", x);
  return buffer;
}
}  // namespace

GcProblem makeGcProblem(const Trajectory& data, const SegmentOptions& options) {
  const int samples = data.numSamples(), n = data.numJoints();
  if (samples < 2) throw InputError("the dataset needs at least 2 samples for GC error segments");
  // Runs: a step longer than 1.5 median steps ends one, as in a `dynid prepare` output split at
  // gaps. The sample period is the mean step within the runs (for one run, (t_end - t_0) /
  // (samples - 1)), and every step within a run must equal it to 1e-6.
  std::vector<double> steps(static_cast<std::size_t>(samples - 1));
  for (int k = 1; k < samples; ++k) steps[k - 1] = data.time[k] - data.time[k - 1];
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                   sorted.end());
  const double median = sorted[sorted.size() / 2];
  if (!(median > 0.0)) throw InputError("the dataset's time stamps do not increase");
  std::vector<std::pair<int, int>> runs;  // [begin, end) sample ranges
  int begin = 0;
  for (int k = 1; k < samples; ++k)
    if (steps[k - 1] > 1.5 * median) {
      runs.emplace_back(begin, k);
      begin = k;
    }
  runs.emplace_back(begin, samples);
  double span = 0.0;
  int intervals = 0;
  for (const auto& [b, e] : runs) {
    span += data.time[e - 1] - data.time[b];
    intervals += e - 1 - b;
  }
  const double period = runs.size() == 1 ? (data.time[samples - 1] - data.time[0]) / (samples - 1)
                                         : span / std::max(intervals, 1);
  for (int k = 1; k < samples; ++k) {
    const double step = steps[k - 1];
    if (step <= 1.5 * median && std::abs(step - period) > 1e-6 * period)
      throw InputError("GC error needs a constant sample period; samples " + std::to_string(k) +
                       " and " + std::to_string(k + 1) + " are " + std::to_string(step) +
                       " s apart, not " + std::to_string(period) +
                       " (resample the log with dynid prepare)");
  }
  if (!(options.horizon > 0.0)) throw InputError("the horizon must be positive");
  const double per = options.horizon / period;
  const double step = options.step > 0.0 ? options.step : period;
  if (!(options.horizon / step <= kMaxSegmentSteps))
    throw InputError("a segment of " + std::to_string(options.horizon) + " s in steps of " +
                     std::to_string(step) + " s is " + formatCount(options.horizon / step) +
                     " integration steps, more than " + formatCount(kMaxSegmentSteps) +
                     ": shorten the horizon or lengthen the step");
  const int segment_samples = static_cast<int>(std::lround(per));
  if (segment_samples < 1 || std::abs(per - segment_samples) > 1e-6 * per)
    throw InputError("the horizon " + std::to_string(options.horizon) +
                     " s is not a whole number of sample periods (" + std::to_string(period) +
                     " s)");
  GcProblem problem;
  problem.data = data;
  problem.samples_per_segment = segment_samples;
  problem.integrator = options.integrator;
  problem.step = step;
  const double sub = period / problem.step;
  problem.substeps = static_cast<int>(std::lround(sub));
  if (problem.substeps < 1 || std::abs(sub - problem.substeps) > 1e-6 * sub)
    throw InputError("the integration step does not divide the sample period");
  // Segments never cross a run boundary: non-overlapping slots per run, and valid random starts.
  std::vector<long> slots, valid;  // per run
  long available = 0, starts_total = 0;
  for (const auto& [b, e] : runs) {
    slots.push_back((e - b - 1) / segment_samples);
    valid.push_back(std::max(0, e - b - segment_samples));
    available += slots.back();
    starts_total += valid.back();
  }
  if (available < 1) throw InputError("the dataset is shorter than one horizon");
  int count = options.num_segments <= 0 ? static_cast<int>(available) : options.num_segments;
  if (!options.random_starts) {
    if (count > available)
      throw InputError("asked for " + std::to_string(count) + " segments of " +
                       std::to_string(options.horizon) + " s; the dataset has room for " +
                       std::to_string(available) + " without overlap");
    // Evenly spaced over the slots of every run.
    for (int s = 0; s < count; ++s) {
      long slot = static_cast<long>(s) * available / count;
      std::size_t r = 0;
      while (slot >= slots[r]) slot -= slots[r++];
      problem.starts.push_back(runs[r].first + static_cast<int>(slot) * segment_samples);
    }
  } else {
    std::mt19937_64 rng(options.seed);
    std::uniform_int_distribution<long> start(0, starts_total - 1);
    for (int s = 0; s < count; ++s) {
      long at = start(rng);
      std::size_t r = 0;
      while (at >= valid[r]) at -= valid[r++];
      problem.starts.push_back(runs[r].first + static_cast<int>(at));
    }
    std::sort(problem.starts.begin(), problem.starts.end());
  }
  problem.weight_q = Eigen::VectorXd::Ones(n);
  problem.weight_dq = Eigen::VectorXd::Ones(n);
  if (options.normalise) {
    // 1 / standard deviation over the dataset (1 for a joint that does not move).
    for (int j = 0; j < n; ++j) {
      const auto spread = [&](const Eigen::MatrixXd& m) {
        const double mean = m.row(j).mean();
        const double sd = std::sqrt((m.row(j).array() - mean).square().mean());
        return sd > 0.0 ? 1.0 / sd : 1.0;
      };
      problem.weight_q[j] = spread(data.q);
      problem.weight_dq[j] = spread(data.dq);
    }
  }
  return problem;
}

GcWorkspace::PerThread::PerThread(const Model& model)
    : model(model), data(model), q(model.numJoints()), dq(model.numJoints()), tau(0) {}

GcWorkspace::GcWorkspace(int num_threads) { threads.resize(static_cast<std::size_t>(num_threads)); }

bool GcStop::requested() const {
  return (flag != nullptr && flag->load(std::memory_order_relaxed)) ||
         (deadline != std::chrono::steady_clock::time_point::max() &&
          std::chrono::steady_clock::now() >= deadline);
}

double gcError(const Model& candidate, const GcProblem& problem, GcWorkspace& workspace,
               ThreadPool& pool, const GcStop& stop) {
  const int n = candidate.numJoints();
  if (problem.data.numJoints() != n)
    throw InputError("the data has " + std::to_string(problem.data.numJoints()) +
                     " joints, the model " + std::to_string(n));
  workspace.segment_errors.resize(problem.numSegments());
  const long evaluation = ++workspace.evaluations;
  std::atomic<bool> stopped{false};
  pool.parallelFor(problem.numSegments(), [&](int s, int thread) {
    if (stopped.load(std::memory_order_relaxed) || stop.requested()) {
      stopped.store(true, std::memory_order_relaxed);
      return;
    }
    // Roll out from the recorded start with the recorded (held) torques.
    // Made on this thread the first time it runs: what a thread writes comes from its own
    // allocator arena, so no cache line is shared with another thread's workspace.
    std::unique_ptr<GcWorkspace::PerThread>& slot = workspace.threads[thread];
    if (!slot) slot = std::make_unique<GcWorkspace::PerThread>(candidate);
    GcWorkspace::PerThread& own = *slot;
    // The pool's other threads read the candidate from a copy in their own memory, refreshed once
    // per evaluation: read in place, its small arrays share cache lines with what the calling
    // thread (thread 0) writes in its arena, and every such write made the other thread's reads
    // miss (two threads 1.78x one, two processes 1.98x). The calling thread reads it in place.
    if (thread != 0 && own.evaluation != evaluation)
      own.model = candidate, own.evaluation = evaluation;
    const Model& model = thread == 0 ? candidate : own.model;
    Eigen::VectorXd& q = own.q;
    Eigen::VectorXd& dq = own.dq;
    const int start = problem.starts[s];
    q = problem.data.q.col(start);
    dq = problem.data.dq.col(start);
    rollOutSegment(model, own.data, problem, s, q, dq, own.tau);
    const int end = start + problem.samples_per_segment;
    const double error =
        (q - problem.data.q.col(end)).cwiseProduct(problem.weight_q).squaredNorm() +
        (dq - problem.data.dq.col(end)).cwiseProduct(problem.weight_dq).squaredNorm();
    workspace.segment_errors[s] =
        std::isfinite(error) ? std::min(error, kMaxSegmentError) : kMaxSegmentError;
  });
  if (stopped.load()) return std::numeric_limits<double>::quiet_NaN();
  double total = 0.0;
  for (int s = 0; s < problem.numSegments(); ++s) total += workspace.segment_errors[s];
  return total;
}

}  // namespace dynid
