#include "search/gc_problem.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {

namespace {
/// The dataset's runs ([begin, end) sample ranges: a step longer than 1.5 median steps ends one,
/// as in a `dynid prepare` output split at gaps) and its sample period (the mean step within the
/// runs; every step within a run must equal it to 1e-6).
std::pair<std::vector<std::pair<int, int>>, double> runsAndPeriod(const Trajectory& data) {
  const int samples = data.numSamples();
  std::vector<double> steps(static_cast<std::size_t>(samples - 1));
  for (int k = 1; k < samples; ++k) steps[k - 1] = data.time[k] - data.time[k - 1];
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                   sorted.end());
  const double median = sorted[sorted.size() / 2];
  if (!(median > 0.0)) throw InputError("the dataset's time stamps do not increase");
  std::vector<std::pair<int, int>> runs;
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
  return {runs, period};
}

/// Segment starts that never cross a run boundary: evenly spaced over the non-overlapping slots
/// of every run, or seeded random valid starts.
std::vector<int> segmentStarts(const std::vector<std::pair<int, int>>& runs, int segment_samples,
                               const SegmentOptions& options) {
  std::vector<long> slots, valid;  // per run
  long available = 0, starts_total = 0;
  for (const auto& [b, e] : runs) {
    slots.push_back((e - b - 1) / segment_samples);
    valid.push_back(std::max(0, e - b - segment_samples));
    available += slots.back();
    starts_total += valid.back();
  }
  if (available < 1) throw InputError("the dataset is shorter than one horizon");
  const int count = options.num_segments <= 0 ? static_cast<int>(available) : options.num_segments;
  std::vector<int> starts;
  if (!options.random_starts) {
    if (count > available)
      throw InputError("asked for " + std::to_string(count) + " segments of " +
                       formatNumber(options.horizon, 6) + " s; the dataset has room for " +
                       std::to_string(available) + " without overlap");
    for (int s = 0; s < count; ++s) {
      long slot = static_cast<long>(s) * available / count;
      std::size_t r = 0;
      while (slot >= slots[r]) slot -= slots[r++];
      starts.push_back(runs[r].first + static_cast<int>(slot) * segment_samples);
    }
    return starts;
  }
  std::mt19937_64 rng(options.seed);
  std::uniform_int_distribution<long> start(0, starts_total - 1);
  for (int s = 0; s < count; ++s) {
    long at = start(rng);
    std::size_t r = 0;
    while (at >= valid[r]) at -= valid[r++];
    starts.push_back(runs[r].first + static_cast<int>(at));
  }
  std::sort(starts.begin(), starts.end());
  return starts;
}

}  // namespace

GcProblem makeGcProblem(const Trajectory& data, const SegmentOptions& options) {
  const int n = data.numJoints();
  if (data.numSamples() < 2)
    throw InputError("the dataset needs at least 2 samples for GC error segments");
  const auto [runs, period] = runsAndPeriod(data);
  if (!(options.horizon > 0.0)) throw InputError("the horizon must be positive");
  const double per = options.horizon / period;
  const double step = options.step > 0.0 ? options.step : period;
  if (!(options.horizon / step <= kMaxSegmentSteps))
    throw InputError("a segment of " + std::to_string(options.horizon) + " s in steps of " +
                     std::to_string(step) + " s is " + formatNumber(options.horizon / step, 3) +
                     " integration steps, more than " + formatNumber(kMaxSegmentSteps, 3) +
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
  problem.starts = segmentStarts(runs, segment_samples, options);
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

GcProblem makeGcProblemUpTo(const Trajectory& data, SegmentOptions options) {
  if (!options.random_starts && options.num_segments > 0) {
    SegmentOptions all = options;
    all.num_segments = 0;
    options.num_segments = std::min(options.num_segments, makeGcProblem(data, all).numSegments());
  }
  return makeGcProblem(data, options);
}

}  // namespace dynid
