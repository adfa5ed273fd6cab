#include "analysis/logs/prepare.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <sstream>
#include <tuple>

#include "analysis/logs/prepare_steps.hpp"
#include "analysis/logs/read_log.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "core/parallel.hpp"
#include "data/io.hpp"

namespace dynid {
using namespace prepare_steps;

namespace {

/// With the log in a scratch file (a long recording), the joints prepared at a time are as many
/// as fit in this many bytes of signal-long vectors (a joint holds two at once): an hour at 1 kHz,
/// two at a time.
constexpr double kSpilledJointBytes = 128e6;

/// Where the runs' samples go: the outcome's trajectories, or scratch files (prepareLog's
/// scratch_dir).
class Destination {
 public:
  Destination(PrepareOutcome& out, int n, Eigen::Index train, Eigen::Index validate,
              const std::string& scratch_dir)
      : out_(out) {
    if (scratch_dir.empty()) {
      for (auto [t, samples] : {std::pair{&out.train, train}, std::pair{&out.validate, validate}}) {
        t->time.resize(samples);
        for (Eigen::MatrixXd* m : {&t->q, &t->dq, &t->ddq, &t->tau}) m->resize(n, samples);
      }
      return;
    }
    train_ = std::make_shared<ScratchDataset>(scratch_dir, n, train);
    validate_ = std::make_shared<ScratchDataset>(scratch_dir, n, validate);
  }
  /// The run's output rows r (span.rows) as value(r), into their slots: `signal` of joint j (the
  /// time: j ignored). Each joint's signals may be stored from its own thread.
  template <typename Value>
  void store(const RunSpan& span, ScratchDataset::Signal signal, int j, Value value) const {
    if (!train_) {
      Eigen::Index next[2] = {span.first_slot[0], span.first_slot[1]};
      const auto matrix = matrixOf(signal);
      for (std::size_t r = 0; r < span.rows.size(); ++r) {
        Trajectory& t = span.held[r] ? out_.validate : out_.train;
        const Eigen::Index slot = next[span.held[r] ? 1 : 0]++;
        (signal == ScratchDataset::kTime ? t.time[slot] : (t.*matrix)(j, slot)) = value(r);
      }
      return;
    }
    // A run's slots are consecutive in each set: written in blocks, each from its first slot.
    constexpr std::size_t kBlock = 1 << 14;
    std::vector<double> blocks[2];
    Eigen::Index first[2] = {span.first_slot[0], span.first_slot[1]};
    const auto flush = [&](int set) {
      if (blocks[set].empty()) return;
      (set == 1 ? validate_ : train_)
          ->write(signal, j, first[set], blocks[set].data(),
                  static_cast<Eigen::Index>(blocks[set].size()));
      first[set] += static_cast<Eigen::Index>(blocks[set].size());
      blocks[set].clear();
    };
    for (std::size_t r = 0; r < span.rows.size(); ++r) {
      const int set = span.held[r] ? 1 : 0;
      blocks[set].push_back(value(r));
      if (blocks[set].size() == kBlock) flush(set);
    }
    flush(0);
    flush(1);
  }
  /// Into the outcome (scratch files).
  void finish() {
    out_.scratch_train = train_;
    out_.scratch_validate = validate_;
  }

 private:
  PrepareOutcome& out_;
  std::shared_ptr<ScratchDataset> train_, validate_;
};

/// A run's signals at the output's rate. Every signal of the run shares its stamps: where the
/// output's samples fall among them is found once (the same values as resampled()). In a scratch
/// file, the signal and the grid a part at a time instead (no run-long grid: the same bits).
class RunResampler {
 public:
  RunResampler(const RawSignals& s, const RunSpan& span, double rate)
      : s_(s), span_(span), rate_(rate) {
    if (!s.spilled) grid_ = linearGrid(time(), s.values(span.begin, 0), rate, span.count);
  }
  /// Column `column` of the signals (1: q_1, ...), resampled.
  Eigen::VectorXd operator()(int column) const {
    const Eigen::Index raw = span_.end - span_.begin;
    if (!s_.spilled) return resampleLinear(grid_, s_.values.col(column).segment(span_.begin, raw));
    return resampleLinear(
        time(), s_.values(span_.begin, 0), rate_, span_.count,
        [&](Eigen::Index first, Eigen::Index length) {
          return s_.column(column, span_.begin + first, length);
        },
        ScratchColumns::kBlockRows);
  }

 private:
  Eigen::Ref<const Eigen::VectorXd> time() const {
    return s_.values.col(0).segment(span_.begin, span_.end - span_.begin);
  }
  const RawSignals& s_;
  const RunSpan& span_;
  double rate_;
  LinearGrid grid_;
};

/// One kept run, joint by joint: resampled, filtered, differentiated, and its trimmed, decimated
/// samples written into the preallocated train and validate sets. `excerpt`: record
/// PrepareOutcome's excerpt from this run.
void prepareRun(const RawSignals& s, const RunSpan& span, const Filters& filters,
                const PrepareOptions& options, bool excerpt, Eigen::VectorXd& noise_sum,
                ThreadPool* pool, const Destination& destination, PrepareOutcome& out) {
  const std::vector<Biquad>& filter = filters.q;
  const int n = s.n, count = span.count;
  const double h = 1.0 / out.rate, t0 = span.run.start + span.run.time_offset;
  const int window = std::min(out.savgol_window, count % 2 == 1 ? count : count - 1);
  const auto differentiate = [&](const Eigen::VectorXd& x, int order) {
    if (!options.savitzky_golay)
      return order == 1 ? derivative(x, h) : derivative(derivative(x, h), h);
    return savitzkyGolay(x, h, window, options.savgol_degree, order);
  };
  const auto store = [&](ScratchDataset::Signal signal, int j, const Eigen::VectorXd& x) {
    destination.store(span, signal, j, [&](std::size_t r) { return x[span.rows[r]]; });
  };
  destination.store(span, ScratchDataset::kTime, 0,
                    [&](std::size_t r) { return t0 + span.rows[r] * h; });
  if (excerpt && !filters.noise().empty()) {
    const int length = std::min(count, static_cast<int>(std::lround(2.0 * out.rate)));
    const int first = (count - length) / 2;
    out.excerpt_time =
        Eigen::VectorXd::LinSpaced(length, t0 + first * h, t0 + (first + length - 1) * h);
    out.excerpt_raw.resize(length, n);
    out.excerpt_filtered.resize(length, n);
  }
  const RunResampler signal(s, span, out.rate);
  // Each joint on its own (its own rows of the outputs, its own noise sum and excerpt column):
  // the same bits on any number of threads. Each signal is stored and freed as soon as it is
  // final, so that a thread holds a few signal-long vectors at a time.
  const auto joint = [&](int j) {
    {
      Eigen::VectorXd tau = signal(1 + n + j);
      if (!filters.noise().empty()) {
        // The noise estimate: the resampled torque minus its filtered self (q's filter, else
        // tau's).
        Eigen::VectorXd smooth = filtfilt(filters.noise(), tau);
        noise_sum[j] += (tau - smooth).squaredNorm();
        const bool same = filters.tau_as_q || filters.q.empty();  // smooth is tau's filter's
        if (!same) smooth = filters.tau.empty() ? tau : filtfilt(filters.tau, tau);
        if (excerpt) {
          const Eigen::Index first = (count - out.excerpt_time.size()) / 2;
          out.excerpt_raw.col(j) = tau.segment(first, out.excerpt_time.size());
          out.excerpt_filtered.col(j) = smooth.segment(first, out.excerpt_time.size());
        }
        tau.swap(smooth);
      }
      store(ScratchDataset::kTau, j, tau);
    }
    Eigen::VectorXd q = signal(1 + j);
    if (!filter.empty()) filtfiltInPlace(filter, q);
    const auto logged = [&](int column) {
      Eigen::VectorXd x = signal(column);
      if (!filter.empty()) filtfiltInPlace(filter, x);
      return x;
    };
    if (!out.dq_derived) {
      // q is final: stored and freed before dq is made (fewer signal-long vectors at a time).
      store(ScratchDataset::kQ, j, q);
      q = Eigen::VectorXd();
      Eigen::VectorXd dq = logged(1 + 2 * n + j);
      const Eigen::VectorXd ddq = out.ddq_logged ? logged(s.ddq_at + j) : differentiate(dq, 1);
      store(ScratchDataset::kDq, j, dq);
      dq = Eigen::VectorXd();
      store(ScratchDataset::kDdq, j, ddq);
      return;
    }
    // dq from q; ddq logged, from q's polynomials (Savitzky-Golay) or of dq (central
    // differences). Each stored and freed as soon as nothing else needs it: two at a time.
    Eigen::VectorXd dq = differentiate(q, 1);
    if (options.savitzky_golay && !out.ddq_logged) {
      store(ScratchDataset::kDq, j, dq);
      dq = Eigen::VectorXd();
      const Eigen::VectorXd ddq = differentiate(q, 2);
      store(ScratchDataset::kQ, j, q);
      q = Eigen::VectorXd();
      store(ScratchDataset::kDdq, j, ddq);
      return;
    }
    store(ScratchDataset::kQ, j, q);
    q = Eigen::VectorXd();
    const Eigen::VectorXd ddq = out.ddq_logged ? logged(s.ddq_at + j) : derivative(dq, h);
    store(ScratchDataset::kDq, j, dq);
    dq = Eigen::VectorXd();
    store(ScratchDataset::kDdq, j, ddq);
  };
  if (pool == nullptr) {
    for (int j = 0; j < n; ++j) joint(j);
    return;
  }
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(n));
  pool->parallelFor(n, [&](int j, int) {
    try {
      joint(j);
    } catch (...) {
      errors[static_cast<std::size_t>(j)] = std::current_exception();  // rethrown below
    }
  });
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);  // the first joint's, whichever thread ran it
}

/// The run's raw torques at its own stamps where two adjacent held-out samples bracket them
/// (appended to times and rows, one joint after another per sample).
void keepRawHeld(const RawSignals& s, const RunSpan& span, double rate, std::vector<double>& times,
                 std::vector<double>& taus) {
  if (span.rows.size() < 2) return;
  const double step = span.rows.size() > 1 ? span.rows[1] - span.rows[0] : 1.0;
  std::vector<Eigen::Index> kept;  // the raw samples held out, then their torques joint by joint
  for (Eigen::Index k = span.begin; k < span.end; ++k) {
    const double u = (s.values(k, 0) - span.run.start) * rate;  // on the run's grid
    const double from = (u - span.rows.front()) / step;
    if (!(from >= 0.0)) continue;
    auto r = static_cast<std::size_t>(std::floor(from));
    if (r + 1 == span.rows.size() && u == span.rows.back()) --r;  // the last sample itself
    if (r + 1 >= span.rows.size() || !span.held[r] || !span.held[r + 1]) continue;
    times.push_back(s.values(k, 0) + span.run.time_offset);
    kept.push_back(k);
  }
  if (kept.empty()) return;
  const std::size_t at = taus.size();
  taus.resize(at + kept.size() * static_cast<std::size_t>(s.n));
  for (int j = 0; j < s.n; ++j) {
    const Eigen::VectorXd tau = s.column(1 + s.n + j, kept.front(), kept.back() - kept.front() + 1);
    for (std::size_t i = 0; i < kept.size(); ++i)
      taus[at + i * static_cast<std::size_t>(s.n) + static_cast<std::size_t>(j)] =
          tau[kept[i] - kept.front()];
  }
}

}  // namespace

double timeUnitScale(const std::string& unit) {
  if (unit == "s") return 1.0;
  if (unit == "ms") return 1e-3;
  if (unit == "us") return 1e-6;
  if (unit == "ns") return 1e-9;
  throw InputError("unknown time unit '" + unit + "' (s, ms, us or ns)");
}

double angleUnitScale(const std::string& unit) {
  if (unit == "rad") return 1.0;
  if (unit == "deg") return std::numbers::pi / 180.0;
  throw InputError("unknown angle unit '" + unit + "' (rad or deg)");
}

namespace {

std::vector<RawSignals> readFiles(const LogSource& source, const PrepareOptions& options,
                                  const std::string& scratch_dir, PrepareOutcome& out) {
  std::vector<RawSignals> files;
  std::vector<std::string> names = source.tables;
  if (names.empty()) names.push_back("");  // the per-signal files
  if (!options.row_windows.empty() && names.size() > 1)
    throw InputError("`rows` applies to one log file; with several, give `window` (times)");
  std::vector<double> all_steps;
  std::vector<char> window_held(options.windows.size(), 0);
  for (const std::string& name : names) {
    files.push_back(readLog(source, name, scratch_dir));
    RawSignals& s = files.back();
    for (const std::string& w : s.warnings) out.warnings.push_back(s.file + ": " + w);
    applyUnits(s, source, options);
    out.raw_samples += static_cast<int>(s.rows);
    out.skipped_missing += s.skipped_missing;
    const std::string label = !name.empty() ? name : source.arrays ? "arrays" : source.time_file;
    if (s.n != files.front().n)
      throw InputError(label + ": " + std::to_string(s.n) + " joints, the first log " +
                       std::to_string(files.front().n));
    if (s.has_dq != files.front().has_dq || s.has_ddq != files.front().has_ddq)
      throw InputError(label + ": dq or ddq is logged in some files and not in others");
    if (!name.empty()) {
      out.columns.push_back(s.columns);
      const std::string mismatch = angleUnitMismatch({s.columns}, options.angle_scale);
      if (!mismatch.empty())
        out.warnings.push_back(label + ": " + mismatch +
                               ": give the `angle_unit` the columns are in");
    }
    alignToLogTime(s, options, files.size() == 1, out);
    keepRows(s, options.row_windows, label);
    sortAndDeduplicate(s, options.max_gap, out);
    const double spans_from = s.rows > 0 ? s.values(0, 0) : 0.0;
    const double spans_to = s.rows > 0 ? s.values(s.rows - 1, 0) : 0.0;
    keepWindows(s, options.windows, window_held);
    if (s.rows < 3) throw InputError(fewStampsMessage(label, options, spans_from, spans_to));
    std::vector<double> st = steps(s);
    if (all_steps.empty())
      all_steps = std::move(st);  // one file: no copy of an hour's steps
    else
      all_steps.insert(all_steps.end(), st.begin(), st.end());
  }
  for (std::size_t w = 0; w < options.windows.size(); ++w)
    if (!window_held[w])
      throw InputError("`window` " + formatNumber(options.windows[w].first) + ":" +
                       formatNumber(options.windows[w].second) +
                       " holds no sample (times are seconds from the log's first stamp)");
  out.median_step = median(std::move(all_steps));
  chooseRate(names.front().empty() ? source.time_file : names.front(), options, out);
  return files;
}
constexpr Eigen::Index kMinTrainSamples = 10;

/// Where the samples go.
struct SamplePlan {
  Eigen::Index train = 0, validate = 0;  // samples in each dataset
  std::size_t longest = 0;               // the longest kept run (its excerpt is the figure's)
};

/// Pass 3: which runs are long enough for the filter, and where their samples go (train or
/// held out: the run when listed, the samples within a validation time range, and the last
/// fraction of every run).
SamplePlan planSamples(std::vector<RunSpan>& spans, const Filters& filters,
                       const PrepareOptions& options, PrepareOutcome& out) {
  int transient = 3;
  for (const std::vector<Biquad>* f : {&filters.q, &filters.tau})
    if (!f->empty()) transient = std::max(transient, padTransient(*f) + 1);
  SamplePlan plan;
  plan.longest = spans.size();
  for (std::size_t r = 0; r < spans.size(); ++r) {
    RunSpan& span = spans[r];
    span.edge = static_cast<int>(std::ceil(out.trim * out.rate));
    // Enough samples for the filter's padding, the derivatives and the trimmed edges.
    span.kept = span.count >= std::max(2 * span.edge + 3, transient);
    if (!span.kept) {
      out.dropped_runs.push_back(span.run);
      continue;
    }
    span.rows = {span.edge, options.decimate,
                 static_cast<std::size_t>((span.count - 2 * span.edge + options.decimate - 1) /
                                          options.decimate)};
    span.first_slot[0] = plan.train;
    span.first_slot[1] = plan.validate;
    const auto split = static_cast<std::size_t>(
        std::floor((1.0 - options.validate_fraction) * static_cast<double>(span.rows.size())));
    const bool whole = std::find(options.validate_runs.begin(), options.validate_runs.end(),
                                 static_cast<int>(out.runs_planned)) != options.validate_runs.end();
    ++out.runs_planned;
    const double t0 = span.run.start + span.run.time_offset;
    for (std::size_t k = 0; k < span.rows.size(); ++k) {
      const double t = t0 + span.rows[k] / out.rate;
      bool held = whole || k >= split;
      for (const auto& [from, to] : options.validate_ranges) held = held || (t >= from && t <= to);
      span.held.push_back(held ? 1 : 0);
      ++(held ? plan.validate : plan.train);
    }
    span.run.samples = static_cast<int>(span.rows.size());
    if (plan.longest == spans.size() || span.count > spans[plan.longest].count) plan.longest = r;
  }
  for (int r : options.validate_runs)
    if (r < 0 || r >= out.runs_planned)
      throw InputError("`validate_runs`: run " + std::to_string(r + 1) +
                       " does not exist: the log has " + std::to_string(out.runs_planned) +
                       " runs long enough for the filter");
  for (const auto& [from, to] : options.validate_ranges) {
    bool holds = false;
    double first = std::numeric_limits<double>::infinity(), last = -first;
    for (const RunSpan& span : spans)
      for (std::size_t k = 0; k < span.rows.size() && !holds; ++k) {
        const double t = span.run.start + span.run.time_offset + span.rows[k] / out.rate;
        holds = t >= from && t <= to;
        first = std::min(first, t);
        last = std::max(last, t);
      }
    if (!holds)
      throw InputError("`validate_time` " + formatNumber(from) + ":" + formatNumber(to) +
                       " holds no sample: the kept runs span " + formatNumber(first, 6) + " to " +
                       formatNumber(last, 6) +
                       " s from the log's first stamp (times are seconds from it, after "
                       "`time_unit`)");
  }
  if (plan.train == 0 && plan.validate > 0)
    throw InputError("every sample is held out for validation: nothing is left to train on");
  if (plan.train == 0)
    throw InputError("no sample left: every run is shorter than the filter's transient (" +
                     formatNumber(out.trim, 6) + " s trimmed at each end); lower `trim` or " +
                     "`max_gap`'s splitting, or raise `cutoff`");
  if (plan.train < kMinTrainSamples)
    throw InputError("only " + std::to_string(plan.train) +
                     " training samples are left after `decimate` " +
                     std::to_string(options.decimate) + " and the held-out samples; " +
                     "identification needs at least " + std::to_string(kMinTrainSamples) +
                     ": lower `decimate` or hold out less");
  return plan;
}

}  // namespace

void PrepareOptions::check() const {
  if (!(time_scale > 0.0) || !(angle_scale > 0.0) || !std::isfinite(time_scale) ||
      !std::isfinite(angle_scale))
    throw InputError("the time and angle units must be positive");
  if (!std::isfinite(cutoff) || !std::isfinite(tau_cutoff))
    throw InputError("cutoff and tau_cutoff must be finite frequencies [Hz]");
  checkOption("prepare", "rate", rate, "`rate`");
  checkOption("prepare", "order", order, "`order`");
  checkOption("prepare", "decimate", decimate, "`decimate`");
  checkOption("prepare", "max-gap", max_gap, "`max_gap`");
  checkOption("prepare", "trim", trim, "`trim`");
  checkOption("prepare", "savgol-window", savgol_window, "`savgol_window`");
  checkOption("prepare", "savgol-degree", savgol_degree, "`savgol_degree`");
  checkOption("prepare", "validate-fraction", validate_fraction, "`validate_fraction`");
  for (const auto& [from, to] : windows)
    if (!(from < to) || !std::isfinite(from) || !std::isfinite(to))
      throw InputError("each window is from:to [s] with from < to, not " + formatNumber(from) +
                       ":" + formatNumber(to));
  for (const auto& [from, to] : row_windows)
    if (from < 1 || to < from)
      throw InputError("each row window is a:b with 1 <= a <= b, not " + std::to_string(from) +
                       ":" + std::to_string(to));
  for (const Eigen::VectorXd* bound : {&dq_bound, &ddq_bound})
    for (Eigen::Index j = 0; j < bound->size(); ++j)
      if (!((*bound)[j] > 0.0))
        throw InputError("the dq and ddq plausibility bounds must be positive");
}

PrepareOutcome prepareLog(const LogSource& source, const PrepareOptions& options, int threads,
                          const std::string& scratch_dir) {
  options.check();
  if (options.keep_raw_torque && options.validate_fraction == 0.0 &&
      options.validate_ranges.empty() && options.validate_runs.empty())
    throw InputError(
        "`keep_raw_torque` keeps the held-out part's raw torques: hold a part out "
        "(`validate_fraction`, `validate_time` or `validate_runs`)");
  checkOption("prepare", "joints", source.num_joints, "`joints`");
  checkOption("prepare", "threads", threads, "`threads`");
  PrepareOutcome out;
  std::vector<RawSignals> files = readFiles(source, options, scratch_dir, out);
  {
    std::vector<std::string> labels = source.tables;
    if (labels.empty()) labels.push_back(source.arrays ? "arrays" : source.time_file);
    findRest(files, labels, out);
  }
  out.order = options.order;
  out.decimate = options.decimate;
  out.dq_derived = !files.front().has_dq || options.derive_dq;
  out.ddq_logged = files.front().has_ddq && !options.derive_ddq;
  std::vector<RunSpan> spans = findRuns(files, options, out);
  double resampled = 0.0, logged = 0.0;
  for (const RunSpan& span : spans) {
    resampled += span.count;
    logged += static_cast<double>(span.end - span.begin);
  }
  if (resampled > kMaxResampledSamples || resampled > kMaxUpsampling * logged)
    throw InputError(resampleBoundMessage(resampled, logged, out.rate));

  // Pass 2: the spectra, and the filter.
  measureSpectra(files, spans, out);
  chooseFilter(options, out);
  const Filters filters = designFilters(options, out);
  const std::vector<Biquad>& filter = filters.q;
  const SamplePlan plan = planSamples(spans, filters, options, out);
  const int n = files.front().n;
  Destination destination(out, n, plan.train, plan.validate, scratch_dir);

  // Pass 4: every kept run, joint by joint (the joints on the threads), into its place. With the
  // log in a scratch file, only as many joints at a time as fit in kSpilledJointBytes.
  std::optional<ThreadPool> pool;
  if (n > 1 && threads != 1) pool.emplace(threads);
  int longest = 0;
  for (const RunSpan& span : spans) longest = std::max(longest, span.kept ? span.count : 0);
  const bool spilled = std::any_of(files.begin(), files.end(),
                                   [](const RawSignals& f) { return f.spilled != nullptr; });
  const int fit = std::max(
      1, static_cast<int>(kSpilledJointBytes / (2.0 * sizeof(double) * std::max(longest, 1))));
  if (pool && spilled && fit < pool->numThreads()) {
    pool.reset();
    if (fit > 1) pool.emplace(fit);
  }
  ThreadPool* joint_pool = pool && pool->numThreads() > 1 ? &*pool : nullptr;
  Eigen::VectorXd noise_sum = Eigen::VectorXd::Zero(n);
  double noise_count = 0.0;
  std::vector<double> raw_times, raw_taus;
  for (std::size_t r = 0; r < spans.size(); ++r) {
    const RunSpan& span = spans[r];
    if (span.kept) {
      prepareRun(files[span.file], span, filters, options, r == plan.longest, noise_sum, joint_pool,
                 destination, out);
      if (options.keep_raw_torque)
        keepRawHeld(files[span.file], span, out.rate, raw_times, raw_taus);
      out.runs.push_back(span.run);
      if (!filters.noise().empty()) noise_count += span.count;
    }
    if (r + 1 == spans.size() || spans[r + 1].file != span.file)
      files[span.file] = RawSignals();  // done with this file
  }
  out.raw_validate_time = Eigen::Map<const Eigen::VectorXd>(
      raw_times.data(), static_cast<Eigen::Index>(raw_times.size()));
  out.raw_validate_tau =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          raw_taus.data(), static_cast<Eigen::Index>(raw_times.size()), n);
  out.tau_noise = noise_count > 0.0 ? Eigen::VectorXd((noise_sum / noise_count).cwiseSqrt())
                                    : Eigen::VectorXd::Zero(n);
  destination.finish();
  checkPlausible(options, n, !filter.empty() || out.ddq_logged, out);
  return out;
}

ScratchDataset::ScratchDataset(const std::string& dir, int num_joints, Eigen::Index samples)
    : n_(num_joints), columns_(dir, 1 + 4 * num_joints, samples) {}

void ScratchDataset::write(Signal signal, int joint, Eigen::Index first, const double* values,
                           Eigen::Index count) {
  columns_.write(index(signal, joint), first, values, count);
}

Eigen::VectorXd ScratchDataset::column(Signal signal, int joint) const {
  Eigen::VectorXd out(numSamples());
  columns_.read(index(signal, joint), 0, out.data(), out.size());
  return out;
}

void ScratchDataset::rows(int first, int last, Trajectory& chunk) const {
  const int count = last - first;
  chunk.time.resize(count);
  columns_.read(0, first, chunk.time.data(), count);
  Eigen::VectorXd row(count);
  for (auto [signal, m] : {std::pair{kQ, &chunk.q}, std::pair{kDq, &chunk.dq},
                           std::pair{kDdq, &chunk.ddq}, std::pair{kTau, &chunk.tau}}) {
    m->resize(n_, count);
    for (int j = 0; j < n_; ++j) {
      columns_.read(index(signal, j), first, row.data(), count);
      m->row(j) = row.transpose();
    }
  }
}

}  // namespace dynid