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

#include "analysis/logs/read_log.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "core/parallel.hpp"
#include "data/io.hpp"

namespace dynid {
namespace {

/// The log's signals in SI units: time and angles scaled, motor currents times torque constant
/// and gear ratio.
void applyUnits(RawSignals& out, const LogSource& source, const PrepareOptions& options) {
  const int n = out.n;
  // Column by column (the signals may be in a scratch file); a scale of 1 changes nothing.
  const auto scale = [&](int first, double factor) {
    if (factor != 1.0)
      for (int c = first; c < first + n; ++c) out.setColumn(c, out.column(c) * factor);
  };
  out.values.col(0) *= options.time_scale;
  scale(1, options.angle_scale);
  if (out.has_dq) scale(1 + 2 * n, options.angle_scale);
  if (out.has_ddq) scale(out.ddq_at, options.angle_scale);
  if (source.current) {
    const auto check = [&](const Eigen::VectorXd& v, const char* what, bool required) {
      if (v.size() == 0 && !required) return;
      if (v.size() != n)
        throw InputError(std::string(what) + " has " + std::to_string(v.size()) +
                         " values; the log (" + out.tau_file + ") has " + std::to_string(n) +
                         " joints: give one per joint");
      for (Eigen::Index j = 0; j < n; ++j)
        if (!std::isfinite(v[j]) || v[j] == 0.0)
          throw InputError(std::string(what) + ": the value of joint " + std::to_string(j + 1) +
                           " must be finite and non-zero");
    };
    check(options.torque_constants, "--torque-constants", true);
    check(options.gear_ratios, "--gear-ratios", false);
    for (int j = 0; j < n; ++j)
      out.setColumn(1 + n + j,
                    out.column(1 + n + j) *
                        (options.torque_constants[j] *
                         (options.gear_ratios.size() > 0 ? options.gear_ratios[j] : 1.0)));
  } else if (options.torque_constants.size() > 0 || options.gear_ratios.size() > 0) {
    throw InputError("torque constants and gear ratios apply to motor currents (--current)");
  }
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// Keeps the rows `kept` (increasing) in place.
void compact(RawSignals& s, const std::vector<Eigen::Index>& kept) { s.keep(kept); }

/// Sorts by time (stable) and keeps the first sample of each repeated stamp; counts both. A stamp
/// that goes back further than the gap limit (`max_gap`, or 5 median forward steps) is not jitter
/// but a clock reset or a second recording appended: sorting would interleave two recordings, so
/// it is a ParseError naming the line.
void sortAndDeduplicate(RawSignals& s, double max_gap, PrepareOutcome& out) {
  if (!(max_gap > 0.0)) {
    std::vector<double> forward;
    for (Eigen::Index k = 1; k < s.rows; ++k)
      if (s.values(k, 0) > s.values(k - 1, 0))
        forward.push_back(s.values(k, 0) - s.values(k - 1, 0));
    max_gap = forward.empty() ? 0.0 : 5.0 * median(std::move(forward));
  }
  bool sorted = true;
  for (Eigen::Index k = 1; k < s.rows; ++k)
    if (s.values(k, 0) < s.values(k - 1, 0)) {
      const double back = s.values(k - 1, 0) - s.values(k, 0);
      if (back > max_gap)
        throw ParseError(s.file, s.line_of ? s.line_of(k) : 0, "time",
                         "the stamp goes back " + formatNumber(back) +
                             " s, more than the gap limit " + formatNumber(max_gap) +
                             " s: a clock reset or two recordings in one file? Split them into "
                             "separate files (prepare --log a.csv b.csv) or raise --max-gap to "
                             "sort them together");
      ++out.unsorted_stamps;
      sorted = false;
    }
  if (!sorted) {
    std::vector<Eigen::Index> order(static_cast<std::size_t>(s.rows));
    std::iota(order.begin(), order.end(), Eigen::Index{0});
    std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
      return s.values(a, 0) < s.values(b, 0);
    });
    s.keep(order);
  }
  std::vector<Eigen::Index> kept;
  kept.reserve(static_cast<std::size_t>(s.rows));
  for (Eigen::Index k = 0; k < s.rows; ++k) {
    if (!kept.empty() && s.values(k, 0) == s.values(kept.back(), 0)) {
      ++out.repeated_stamps;
      continue;
    }
    kept.push_back(k);
  }
  compact(s, kept);
}

/// Per sample: 1 when every signal equals the previous sample's (k > 0), found column by column.
std::vector<char> sameAsPrevious(const RawSignals& s) {
  std::vector<char> same(static_cast<std::size_t>(s.rows), 1);
  if (s.rows > 0) same[0] = 0;
  for (int c = 1; c < s.numColumns(); ++c) {
    const Eigen::VectorXd x = s.column(c);
    for (Eigen::Index k = 1; k < s.rows; ++k)
      if (x[k] != x[k - 1]) same[static_cast<std::size_t>(k)] = 0;
  }
  return same;
}

/// Drops stalled repeats (PrepareOptions::keep_stalled): within each stretch of samples identical
/// to its first, the repeats go when the stretch ends within `max_gap` of its first stamp.
void dropStalled(RawSignals& s, double max_gap, PrepareOutcome& out) {
  std::vector<Eigen::Index> kept;
  kept.reserve(static_cast<std::size_t>(s.rows));
  // Equal to the stretch's first sample = equal to the previous one (finite numbers: transitive).
  const std::vector<char> same = sameAsPrevious(s);
  Eigen::Index k = 0;
  while (k < s.rows) {
    Eigen::Index last = k;
    while (last + 1 < s.rows && same[static_cast<std::size_t>(last + 1)]) ++last;
    kept.push_back(k);
    const double bridged = s.values(last + 1 < s.rows ? last + 1 : last, 0) - s.values(k, 0);
    if (last > k && bridged <= max_gap) {
      out.stalled_repeats += static_cast<int>(last - k);
    } else {
      for (Eigen::Index r = k + 1; r <= last; ++r) kept.push_back(r);
    }
    k = last + 1;
  }
  compact(s, kept);
}

std::vector<double> steps(const RawSignals& s) {
  std::vector<double> out(static_cast<std::size_t>(std::max<Eigen::Index>(s.rows - 1, 0)));
  for (Eigen::Index k = 0; k + 1 < s.rows; ++k) out[k] = s.values(k + 1, 0) - s.values(k, 0);
  return out;
}

/// The resampled samples a run writes: first, first + step, ... (size() of them), without a
/// vector an hour long.
struct RowList {
  int first = 0, step = 1;
  std::size_t count = 0;
  int operator[](std::size_t r) const { return first + static_cast<int>(r) * step; }
  std::size_t size() const { return count; }
  int front() const { return first; }
  int back() const { return (*this)[count - 1]; }
};

/// Consecutive samples of one file without a gap, and where its output goes.
struct RunSpan {
  std::size_t file = 0;
  Eigen::Index begin = 0, end = 0;  // [begin, end) in the file's samples
  PreparedRun run;                  // file and time offset set
  int count = 0, edge = 0;          // resampled samples; trimmed at each end
  bool kept = false;                // long enough for the filter
  RowList rows;                     // the resampled samples written (trimmed, decimated)
  std::vector<char> held;           // per row: 1 when it goes to the validate set
  /// The train and validate sets' samples of the run's first row in each: its rows of either set
  /// follow one another from there.
  Eigen::Index first_slot[2] = {0, 0};
};

// The most samples a log is resampled to, over all its runs (about 14 h at 1 kHz), and the most
// per logged sample: beyond either, --rate is a mistake and the work would run for hours.
constexpr double kMaxResampledSamples = 5e7;
constexpr double kMaxUpsampling = 100.0;

std::string resampleBoundMessage(double samples, double raw, double rate) {
  return "resampling at --rate " + formatNumber(rate) + " Hz makes " + formatNumber(samples, 3) +
         " samples from " + formatNumber(raw, 3) + " logged ones; dynid prepares at most " +
         formatNumber(kMaxResampledSamples, 3) + " samples and " + formatNumber(kMaxUpsampling) +
         " per logged sample: lower --rate (0: the log's median rate)";
}

int resampledCount(const RawSignals& s, const RunSpan& span, double rate) {
  const double count =
      std::floor((s.values(span.end - 1, 0) - s.values(span.begin, 0)) * rate + 1e-9) + 1.0;
  if (!(count <= kMaxResampledSamples))
    throw InputError(resampleBoundMessage(count, static_cast<double>(span.end - span.begin), rate));
  return static_cast<int>(count);
}

/// Column `column` of the signals over the span, resampled to the uniform rate: `count` samples
/// from the span's `first` resampled sample on.
Eigen::VectorXd resampled(const RawSignals& s, const RunSpan& span, Eigen::Index column,
                          double rate, int count, int first = 0) {
  const double t0 = s.values(span.begin, 0) + first / rate;
  // The raw samples around [t0, t0 + (count - 1) / rate].
  const auto time = s.values.col(0).segment(span.begin, span.end - span.begin);
  Eigen::Index a = 0, b = time.size();
  if (first > 0) {
    a = std::upper_bound(time.begin(), time.end(), t0) - time.begin();
    a = std::max<Eigen::Index>(a - 1, 0);
    b = std::upper_bound(time.begin() + a, time.end(), t0 + (count - 1) / rate) - time.begin();
    b = std::min<Eigen::Index>(b + 1, time.size());
  }
  return resampleLinear(time.segment(a, b - a), s.column(column, span.begin + a, b - a), t0, rate,
                        count)
      .col(0);
}

/// Spectra of q and tau over every run at least one segment long (each joint normalised to unit
/// power, then summed), the trajectory band and the noise edge.
void measureSpectra(const std::vector<RawSignals>& files, const std::vector<RunSpan>& spans,
                    PrepareOutcome& out) {
  int longest = 0;
  for (const RunSpan& span : spans) longest = std::max(longest, span.count);
  // Resolution: segments of up to 16 s (a power of two), at least 64 samples.
  int segment = 64;
  while (2 * segment <= longest && 2 * segment <= 16.0 * out.rate) segment *= 2;
  if (longest < segment) return;
  const int n = files.front().n;
  std::vector<Eigen::VectorXd> q_sum(static_cast<std::size_t>(n)), tau_sum(q_sum);
  for (const RunSpan& span : spans) {
    if (span.count < segment) continue;
    const RawSignals& s = files[span.file];
    // Welch's segments with 50 % overlap, at most 16 spread evenly over the run (bounded time on
    // long logs), each resampled on its own. Weighted by the run's length: long runs dominate.
    const int welch = (span.count - segment) / (segment / 2) + 1;
    const int windows = std::min(16, welch);
    const double weight = static_cast<double>(span.count) / windows;
    for (int w = 0; w < windows; ++w) {
      const int first = windows == 1
                            ? 0
                            : static_cast<int>(std::lround(static_cast<double>(w) *
                                                           (span.count - segment) / (windows - 1)));
      for (int j = 0; j < n; ++j) {
        const Spectrum sq = welchSpectrum(resampled(s, span, 1 + j, out.rate, segment, first),
                                          out.rate, segment, 1);
        const Spectrum st = welchSpectrum(resampled(s, span, 1 + n + j, out.rate, segment, first),
                                          out.rate, segment, 1);
        if (q_sum[j].size() == 0) {
          q_sum[j] = Eigen::VectorXd::Zero(sq.density.size());
          tau_sum[j] = q_sum[j];
          out.q_spectrum.frequency = sq.frequency;
        }
        q_sum[j] += weight * sq.density;
        tau_sum[j] += weight * st.density;
      }
    }
  }
  out.q_spectrum.density = Eigen::VectorXd::Zero(out.q_spectrum.frequency.size());
  out.tau_spectrum = out.q_spectrum;
  for (int j = 0; j < n; ++j) {
    // Unit power without the DC bin (the detrended mean's leakage).
    const double q_power = q_sum[j].tail(q_sum[j].size() - 1).sum();
    const double tau_power = tau_sum[j].tail(tau_sum[j].size() - 1).sum();
    if (q_power > 0.0) out.q_spectrum.density += q_sum[j] / q_power;
    if (tau_power > 0.0) out.tau_spectrum.density += tau_sum[j] / tau_power;
  }
  const Eigen::VectorXd& d = out.q_spectrum.density;
  const Eigen::VectorXd& f = out.q_spectrum.frequency;
  const double total = d.tail(d.size() - 1).sum();
  if (!(total > 0.0)) return;  // q never moves
  double cumulative = 0.0;
  Eigen::Index band = 1;
  for (; band < d.size(); ++band) {
    cumulative += d[band];
    if (cumulative >= 0.995 * total) break;
  }
  band = std::min(band, d.size() - 1);
  out.trajectory_band = f[band];
  // The noise floor: the median density from ten times the band to a quarter of the rate (above
  // it, the resampling's interpolation bends the floor down), else over the upper half.
  std::vector<double> upper;
  for (Eigen::Index k = band; k < d.size(); ++k)
    if (f[k] >= 10.0 * out.trajectory_band && f[k] <= out.rate / 4.0) upper.push_back(d[k]);
  if (upper.size() < 8) {
    upper.clear();
    for (Eigen::Index k = d.size() / 2; k < d.size(); ++k) upper.push_back(d[k]);
  }
  const double floor = median(upper);
  out.noise_edge = f[d.size() - 1];
  for (Eigen::Index k = band; k < d.size(); ++k)
    if (d[k] <= 10.0 * floor) {
      out.noise_edge = f[k];
      break;
    }
}

std::string hz(double f) { return formatNumber(f, 3) + " Hz"; }

/// Chooses the cutoff (and says why), the trim and the Savitzky-Golay window.
void chooseFilter(const PrepareOptions& options, PrepareOutcome& out) {
  if (options.auto_cutoff) {
    if (out.q_spectrum.density.size() == 0 || !(out.trajectory_band > 0.0))
      throw InputError("--cutoff auto needs a moving run of at least 64 samples; give --cutoff");
    const double chosen = std::min({5.0 * out.trajectory_band, out.noise_edge, out.rate / 4.0});
    out.cutoff = std::max(chosen, std::min(1.5 * out.trajectory_band, 0.45 * out.rate));
    out.cutoff_reason = "auto: 99.5 % of q's power lies below " + hz(out.trajectory_band) +
                        " (the trajectory band); the cutoff is " + hz(out.cutoff) +
                        ", five times that, at most where q's spectrum meets its noise floor (" +
                        hz(out.noise_edge) + ") and a quarter of the rate";
  } else if (options.cutoff >= 0.0) {
    out.cutoff = options.cutoff;
    out.cutoff_reason = options.cutoff > 0.0 ? "given" : "no filter (--cutoff 0)";
  } else {
    out.cutoff = std::min(10.0, out.rate / 4.0);
    out.cutoff_reason = out.cutoff == 10.0 ? "the default, 10 Hz"
                                           : "the default for logs slower than 40 Hz: a quarter "
                                             "of the rate";
  }
  out.tau_cutoff = options.tau_cutoff < 0.0 ? out.cutoff : options.tau_cutoff;
  // The default trim: two periods of the lowest cutoff (the slowest filter's transient).
  double lowest = 0.0;
  for (double c : {out.cutoff, out.tau_cutoff})
    if (c > 0.0) lowest = lowest > 0.0 ? std::min(lowest, c) : c;
  out.trim = options.trim >= 0.0 ? options.trim : (lowest > 0.0 ? 2.0 / lowest : 0.0);
  // A low-pass within five times the motion's band takes part of the motion with the noise;
  // friction suffers first (docs/MODEL.md, "Friction and filtering").
  if (out.trajectory_band > 0.0 && lowest > 0.0 && lowest < 5.0 * out.trajectory_band)
    out.warnings.push_back(
        "the low-pass at " + hz(lowest) + " is within five times q's trajectory band (" +
        hz(out.trajectory_band) +
        "): it smooths the motion itself, and Coulomb friction comes out low and viscous "
        "friction high (a simulated Panda filtered at 2.7 times its band: Fc 0.46-0.81x, Fv "
        "1.8-2.7x the truth; docs/MODEL.md, \"Friction and filtering\"); raise --cutoff (and "
        "--tau-cutoff) towards " +
        hz(5.0 * out.trajectory_band) + " if q's noise allows");
  if (!options.savitzky_golay) return;
  if (options.savgol_degree < 2 || options.savgol_degree > 6)
    throw InputError("the Savitzky-Golay degree must be 2 to 6 (ddq needs 2), not " +
                     std::to_string(options.savgol_degree));
  if (options.savgol_window > 0 &&
      (options.savgol_window % 2 == 0 || options.savgol_window <= options.savgol_degree))
    throw InputError("the Savitzky-Golay window must be odd and longer than the degree, not " +
                     std::to_string(options.savgol_window));
  // Default: about a quarter period of the cutoff (10 Hz without a filter).
  const double reference = out.cutoff > 0.0 ? out.cutoff : 10.0;
  int minimum = options.savgol_degree + 2;
  if (minimum % 2 == 0) ++minimum;
  out.savgol_window =
      options.savgol_window > 0
          ? options.savgol_window
          : std::max(minimum, 2 * static_cast<int>(std::lround(out.rate / (8.0 * reference))) + 1);
}

/// The low-passes: q's (and dq's, ddq's) and tau's (the same unless --tau-cutoff says otherwise).
struct Filters {
  std::vector<Biquad> q, tau;
  bool tau_as_q = true;
  /// The filter that measures the torque noise: q's, else tau's.
  const std::vector<Biquad>& noise() const { return q.empty() ? tau : q; }
};

/// The trajectory's matrix holding `signal` (the time: none; tau's, unused).
Eigen::MatrixXd Trajectory::*matrixOf(ScratchDataset::Signal signal) {
  switch (signal) {
    case ScratchDataset::kQ:
      return &Trajectory::q;
    case ScratchDataset::kDq:
      return &Trajectory::dq;
    case ScratchDataset::kDdq:
      return &Trajectory::ddq;
    default:
      return &Trajectory::tau;
  }
}

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

/// Keeps the data rows in `windows` (1-based, in file order), before anything reorders them; the
/// line numbers follow.
void keepRows(RawSignals& s, const std::vector<std::pair<long, long>>& windows,
              const std::string& label) {
  if (windows.empty()) return;
  std::vector<Eigen::Index> kept;
  for (Eigen::Index k = 0; k < s.rows; ++k)
    for (const auto& [from, to] : windows)
      if (k + 1 >= from && k + 1 <= to) {
        kept.push_back(k);
        break;
      }
  for (const auto& [from, to] : windows)
    if (from > s.rows)
      throw InputError("--rows " + std::to_string(from) + ":" + std::to_string(to) + ": " + label +
                       " has " + std::to_string(s.rows) + " data rows");
  if (s.line_of) s.line_of = [lines = s.line_of, kept](Eigen::Index k) { return lines(kept[k]); };
  compact(s, kept);
}

/// Keeps the samples within `windows` [s] (times from the log's first stamp).
void keepWindows(RawSignals& s, const std::vector<std::pair<double, double>>& windows,
                 std::vector<char>& held) {
  if (windows.empty()) return;
  std::vector<Eigen::Index> kept;
  for (Eigen::Index k = 0; k < s.rows; ++k)
    for (std::size_t w = 0; w < windows.size(); ++w)
      if (s.values(k, 0) >= windows[w].first && s.values(k, 0) <= windows[w].second) {
        kept.push_back(k);
        held[w] = 1;
        break;
      }
  compact(s, kept);
}

/// The nominal rate near `rate` (the median step's): the nearest round rate (a whole number of Hz
/// below 100 Hz, of 10 Hz above) or round step (a whole number of 0.1 ms: 3 ms is 333.33 Hz),
/// when within 0.1 % of it; else `rate` itself. Says which.
double nominalRate(double rate, std::string& reason) {
  const double whole_hz = rate < 100.0 ? std::round(rate) : 10.0 * std::round(rate / 10.0);
  const double step = std::round(1e4 / rate) * 1e-4;  // in 0.1 ms
  double best = rate;
  for (double candidate : {whole_hz, step > 0.0 ? 1.0 / step : 0.0})
    if (candidate > 0.0 && std::abs(candidate - rate) <= 1e-3 * rate &&
        (best == rate || std::abs(candidate - rate) < std::abs(best - rate)))
      best = candidate;
  reason = best == rate
               ? "the median step's rate, " + formatNumber(rate, 6) +
                     " Hz (no nominal rate within 0.1 %)"
               : "the median step's rate, " + formatNumber(rate, 6) +
                     " Hz, rounded to the nominal " + formatNumber(best, 6) + " Hz (within 0.1 %)";
  return best;
}

/// Every file read, in SI units, from the log's first stamp, windowed, sorted and de-duplicated;
/// out's raw counts and the defaults that come from the median step over all files (rate, gap
/// limit).
/// Whether a column name states an angle unit: "deg" (deg, degree, degrees) or "rad" (rad,
/// radian, radians) as a word of its own ("q1[deg]", "pos_deg", "A1 (rad)"), else "".
std::string angleUnitNamed(const std::string& name) {
  std::string lower = name;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const auto& [word, unit] :
       {std::pair{"degrees", "deg"}, std::pair{"degree", "deg"}, std::pair{"deg", "deg"},
        std::pair{"radians", "rad"}, std::pair{"radian", "rad"}, std::pair{"rad", "rad"}}) {
    const std::string w = word;
    for (std::size_t at = lower.find(w); at != std::string::npos; at = lower.find(w, at + 1)) {
      const std::size_t after = at + w.size();
      const bool starts = at == 0 || !std::isalpha(static_cast<unsigned char>(lower[at - 1]));
      const bool ends =
          after == lower.size() || !std::isalpha(static_cast<unsigned char>(lower[after]));
      if (starts && ends) return unit;
    }
  }
  return "";
}

/// A q or dq column whose name states another angle unit than the one given (e.g.
/// "AxisPos_A1[deg]" read as radians), as "'NAME' says UNIT", or "".
std::string angleUnitMismatch(const std::vector<LogColumns>& files, double angle_scale) {
  const std::string given = angle_scale == 1.0 ? "rad" : "deg";
  for (const LogColumns& c : files)
    for (const auto* names : {&c.q, &c.dq})
      for (const std::string& name : *names) {
        const std::string named = angleUnitNamed(name);
        if (!named.empty() && named != given)
          return "the column '" + name + "' says " + (named == "deg" ? "degrees" : "radians") +
                 ", read as " + (given == "deg" ? "degrees" : "radians") + " (--angle-unit " +
                 given + ")";
      }
  return "";
}

std::vector<RawSignals> readFiles(const LogSource& source, const PrepareOptions& options,
                                  const std::string& scratch_dir, PrepareOutcome& out) {
  std::vector<RawSignals> files;
  std::vector<std::string> names = source.tables;
  if (names.empty()) names.push_back("");  // the per-signal files
  if (!options.row_windows.empty() && names.size() > 1)
    throw InputError("--rows applies to one log file; with several, give --window (times)");
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
                               ": give the --angle-unit the columns are in");
    }
    // Stamps from the log's first one: exact differences of the 64-bit stamps (epochs in ns).
    // Units per second as a whole number when it is one (ns: 1e9), so that a 1.7e18 ns epoch is
    // divided exactly rather than multiplied by the double nearest 1e-9 (off by 1e-7 s).
    const long double per_second = std::round(1.0L / static_cast<long double>(options.time_scale));
    const long double file_origin =
        std::abs(per_second * options.time_scale - 1.0L) < 1e-12L
            ? s.time_origin / per_second
            : s.time_origin * static_cast<long double>(options.time_scale);
    if (files.size() == 1) {  // the first file's earliest stamp (before any window) starts the log
      const double earliest = s.values.col(0).head(s.rows).minCoeff();
      out.time_origin = file_origin + earliest;
      s.values.col(0).head(s.rows).array() -= earliest;
    } else {
      s.values.col(0).head(s.rows).array() += static_cast<double>(file_origin - out.time_origin);
    }
    keepRows(s, options.row_windows, label);
    sortAndDeduplicate(s, options.max_gap, out);
    const double spans_from = s.rows > 0 ? s.values(0, 0) : 0.0;
    const double spans_to = s.rows > 0 ? s.values(s.rows - 1, 0) : 0.0;
    keepWindows(s, options.windows, window_held);
    if (s.rows < 3) {
      std::string windows;
      for (const auto& [from, to] : options.windows)
        windows += (windows.empty() ? "" : ",") + formatNumber(from) + ":" + formatNumber(to);
      std::string message = label + ": fewer than 3 distinct time stamps";
      if (!options.windows.empty() || !options.row_windows.empty())
        message.append(" within ")
            .append(options.windows.empty() ? std::string("the --rows given")
                                            : std::string("--window ").append(windows))
            .append(" (the log spans ")
            .append(formatNumber(spans_from, 6))
            .append(" to ")
            .append(formatNumber(spans_to, 6))
            .append(" s from its first stamp)");
      throw InputError(message);
    }
    std::vector<double> st = steps(s);
    if (all_steps.empty())
      all_steps = std::move(st);  // one file: no copy of an hour's steps
    else
      all_steps.insert(all_steps.end(), st.begin(), st.end());
  }
  for (std::size_t w = 0; w < options.windows.size(); ++w)
    if (!window_held[w])
      throw InputError("--window " + formatNumber(options.windows[w].first) + ":" +
                       formatNumber(options.windows[w].second) +
                       " holds no sample (times are seconds from the log's first stamp)");
  out.median_step = median(std::move(all_steps));
  const std::string& first = names.front().empty() ? source.time_file : names.front();
  if (out.median_step > kSlowestStep || out.median_step < kFastestStep)
    throw InputError(
        first + ": the median step between time stamps is " + formatNumber(out.median_step, 4) +
        " s (" + formatNumber(1.0 / out.median_step, 4) + " Hz), " +
        (out.median_step > kSlowestStep
             ? "too slow to identify a robot's dynamics: if the stamps are not in seconds, give "
               "--time-unit ms, us or ns"
             : "faster than robots log: are the stamps in a larger unit than --time-unit says "
               "(seconds read as milliseconds)?"));
  if (options.rate > 0.0) {
    out.rate = options.rate;
    out.rate_reason = "given";
  } else {
    out.rate = nominalRate(1.0 / out.median_step, out.rate_reason);
  }
  out.max_gap = options.max_gap > 0.0 ? options.max_gap : 5.0 * out.median_step;
  return files;
}

/// Where each recording rests (or creeps) at its ends, with a warning when that is 10 % of it or
/// more: rest identifies gravity and offsets only and outweighs the motion in a least-squares fit.
void findRest(const std::vector<RawSignals>& files, const std::vector<std::string>& labels,
              PrepareOutcome& out) {
  for (std::size_t f = 0; f < files.size(); ++f) {
    const RawSignals& s = files[f];
    // The first sample where any joint has moved from its first position by more than
    // max(1 mrad, 1 % of its range), and the last where any is that far from its last one: joint
    // by joint (the signals may be in a scratch file).
    Eigen::Index first = s.rows - 1, last = -1;
    for (int j = 0; j < s.n; ++j) {
      const Eigen::VectorXd q = s.column(1 + j);
      const double moved = std::max(0.01 * (q.maxCoeff() - q.minCoeff()), 1e-3);
      for (Eigen::Index k = 0; k < first; ++k)
        if (std::abs(q[k] - q[0]) > moved) {
          first = k;
          break;
        }
      for (Eigen::Index k = s.rows - 1; k > last; --k)
        if (std::abs(q[k] - q[s.rows - 1]) > moved) {
          last = k;
          break;
        }
    }
    last = std::max(last, first);
    RestAtEnds rest;
    rest.file = static_cast<int>(f);
    rest.start = s.values(0, 0);
    rest.end = s.values(s.rows - 1, 0);
    rest.leading = s.values(first, 0) - rest.start;
    rest.trailing = rest.end - s.values(last, 0);
    out.rest.push_back(rest);
    const double duration = rest.end - rest.start;
    if (!(duration > 0.0) || rest.leading + rest.trailing < 0.1 * duration) continue;
    out.warnings.push_back(
        labels[f] + ": the robot is at rest (or barely moves) for the first " +
        formatNumber(rest.leading, 3) + " s and the last " + formatNumber(rest.trailing, 3) +
        " s, " + formatNumber(100.0 * (rest.leading + rest.trailing) / duration, 2) + " % of its " +
        formatNumber(duration, 4) +
        " s; rest identifies only gravity and offsets and outweighs "
        "the motion: crop it with --window " +
        formatNumber(s.values(first, 0), 6) + ":" + formatNumber(s.values(last, 0), 6));
  }
}

/// Pass 1: stalls dropped, steps measured, later files shifted after earlier ones, and the runs
/// between gaps.
std::vector<RunSpan> findRuns(std::vector<RawSignals>& files, const PrepareOptions& options,
                              PrepareOutcome& out) {
  out.min_step = std::numeric_limits<double>::infinity();
  std::vector<RunSpan> spans;
  double previous_end = -std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < files.size(); ++f) {
    RawSignals& s = files[f];
    if (!options.keep_stalled) dropStalled(s, out.max_gap, out);
    const std::vector<double> st = steps(s);
    out.min_step = std::min(out.min_step, *std::min_element(st.begin(), st.end()));
    out.max_step = std::max(out.max_step, *std::max_element(st.begin(), st.end()));
    RunSpan span;
    span.file = f;
    span.run.file = static_cast<int>(f);
    const double spacing = std::max(1.0, 2.0 * out.max_gap);
    if (f > 0 && s.values(0, 0) < previous_end + spacing)
      span.run.time_offset = previous_end + spacing - s.values(0, 0);
    previous_end = s.values(s.rows - 1, 0) + span.run.time_offset;
    for (Eigen::Index k = 0; k <= s.rows - 1; ++k)
      if (k + 1 == s.rows || st[static_cast<std::size_t>(k)] > out.max_gap) {
        if (k + 1 < s.rows)
          out.gaps.emplace_back(s.values(k, 0) + span.run.time_offset,
                                st[static_cast<std::size_t>(k)]);
        span.end = k + 1;
        span.count = resampledCount(s, span, out.rate);
        span.run.start = s.values(span.begin, 0);
        span.run.end = s.values(span.end - 1, 0);
        span.run.raw_samples = static_cast<int>(span.end - span.begin);
        spans.push_back(span);
        span.begin = k + 1;
      }
  }
  return spans;
}

/// The fewest training samples a prepared dataset may have (a dataset of a few rows identifies
/// nothing; it is a --decimate or --validate-* mistake).
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
      throw InputError("--validate-runs: run " + std::to_string(r + 1) +
                       " does not exist: the log has " + std::to_string(out.runs_planned) +
                       " runs long enough for the filter");
  for (const auto& [from, to] : options.validate_ranges) {
    bool holds = false;
    for (const RunSpan& span : spans)
      for (std::size_t k = 0; k < span.rows.size() && !holds; ++k) {
        const double t = span.run.start + span.run.time_offset + span.rows[k] / out.rate;
        holds = t >= from && t <= to;
      }
    if (!holds)
      throw InputError("--validate-time " + formatNumber(from) + ":" + formatNumber(to) +
                       " holds no sample: the kept runs lie outside it (times are the log's, in "
                       "seconds after --time-unit)");
  }
  if (plan.train == 0 && plan.validate > 0)
    throw InputError("every sample is held out for validation: nothing is left to train on");
  if (plan.train == 0)
    throw InputError("no sample left: every run is shorter than the filter's transient (" +
                     std::to_string(out.trim) + " s trimmed at each end); lower --trim or " +
                     "--max-gap's splitting, or raise --cutoff");
  if (plan.train < kMinTrainSamples)
    throw InputError("only " + std::to_string(plan.train) +
                     " training samples are left after --decimate " +
                     std::to_string(options.decimate) + " and the held-out samples; " +
                     "identification needs at least " + std::to_string(kMinTrainSamples) +
                     ": lower --decimate or hold out less");
  return plan;
}

/// The per-joint bounds of `given` (empty: `fallback` for all; one value: for all).
Eigen::VectorXd boundsOf(const Eigen::VectorXd& given, double fallback, int n, const char* what) {
  if (given.size() == 0) return Eigen::VectorXd::Constant(n, fallback);
  if (given.size() == 1) return Eigen::VectorXd::Constant(n, given[0]);
  if (given.size() != n)
    throw InputError(std::string(what) + " has " + std::to_string(given.size()) +
                     " values; the log has " + std::to_string(n) +
                     " joints: give one or one per "
                     "joint");
  return given;
}

/// Every sample of one signal of joint j (the time: j ignored), the train set's then the validate
/// set's.
Eigen::VectorXd allSamples(const PrepareOutcome& out, ScratchDataset::Signal signal, int j) {
  const Eigen::Index train = out.trainSamples(), validate = out.validateSamples();
  Eigen::VectorXd all(train + validate);
  if (out.scratch_train) {
    if (train > 0) all.head(train) = out.scratch_train->column(signal, j);
    if (validate > 0) all.tail(validate) = out.scratch_validate->column(signal, j);
    return all;
  }
  // Each set's samples when it has any (an empty set's matrices hold no storage to take a row of).
  for (const auto& [t, at, count] :
       {std::tuple{&out.train, Eigen::Index{0}, train}, std::tuple{&out.validate, train, validate}})
    if (count > 0)
      all.segment(at, count) = signal == ScratchDataset::kTime
                                   ? t->time
                                   : Eigen::VectorXd((t->*matrixOf(signal)).row(j).transpose());
  return all;
}

/// Row j of a signal over the train and validate sets: the 99th percentile of its magnitude (spikes
/// aside), its peak and the sample of the peak (train then validate).
struct Magnitude {
  double p99 = 0.0, peak = 0.0;
  Eigen::Index at = 0;
};
Magnitude magnitudeOf(const PrepareOutcome& out, ScratchDataset::Signal signal, int j) {
  Magnitude m;
  Eigen::VectorXd all = allSamples(out, signal, j).cwiseAbs();
  for (Eigen::Index k = 0; k < all.size(); ++k)
    if (all[k] > m.peak) m.peak = all[k], m.at = k;
  const auto at =
      static_cast<std::ptrdiff_t>(std::floor(0.99 * static_cast<double>(all.size() - 1)));
  std::nth_element(all.begin(), all.begin() + at, all.end());
  m.p99 = all[at];
  return m;
}

/// Velocities and accelerations no robot reaches are a unit or column mistake, never data: an
/// InputError naming the joint, the value, the likely causes and the options that fix them. A
/// log whose joints barely move gets a warning (the stamps may be in a smaller unit than given).
/// The angle-unit mismatch as the first sentence of an error ("" when there is none).
std::string unitHint(const PrepareOutcome& out, const PrepareOptions& options) {
  const std::string mismatch = angleUnitMismatch(out.columns, options.angle_scale);
  return mismatch.empty() ? "" : "First: " + mismatch + ". ";
}

void checkPlausible(const PrepareOptions& options, int n, bool ddq_meaningful,
                    PrepareOutcome& out) {
  const Eigen::VectorXd dq_bound = boundsOf(options.dq_bound, kPlausibleSpeed, n, "--dq-max");
  const Eigen::VectorXd ddq_bound =
      boundsOf(options.ddq_bound, kPlausibleAcceleration, n, "--ddq-max");
  double fastest = 0.0;
  for (int j = 0; j < n; ++j)
    for (int order : {1, 2}) {
      if (order == 2 && !ddq_meaningful) continue;
      const Magnitude m =
          magnitudeOf(out, order == 1 ? ScratchDataset::kDq : ScratchDataset::kDdq, j);
      if (order == 1) fastest = std::max(fastest, m.p99);
      const double bound = (order == 1 ? dq_bound : ddq_bound)[j];
      if (!(m.p99 > bound)) continue;
      const bool given = (order == 1 ? options.dq_bound : options.ddq_bound).size() > 0;
      throw InputError(
          "joint " + std::to_string(j + 1) + ": |" + (order == 1 ? "dq" : "ddq") + "| reaches " +
          formatNumber(m.peak, 4) + (order == 1 ? " rad/s" : " rad/s^2") +
          " at t = " + formatNumber(allSamples(out, ScratchDataset::kTime, 0)[m.at], 6) +
          " s and exceeds " + formatNumber(bound, 4) + " for over 1 % of the samples, more than " +
          (given ? std::string("the bound (--dq-max, --ddq-max, or 3 times --robot's limits)")
                 : std::string("any robot moves")) +
          ": the log's units or columns are likely wrong. " + unitHint(out, options) +
          "Check --time-unit (stamps in a larger "
          "unit than given make motion look fast), --angle-unit (degrees read as radians: 57 "
          "times) and the --q columns (positions, in joint order?); if the motion is real, raise " +
          (order == 1 ? "--dq-max" : "--ddq-max"));
    }
  if (fastest < 1e-3)
    out.warnings.push_back("no joint moves faster than " + formatNumber(fastest, 3) +
                           " rad/s for 1 % of the time: the robot barely moves, or the stamps are "
                           "in a smaller unit than --time-unit says (milliseconds read as "
                           "seconds make motion look 1000 times slower)");
}

}  // namespace

void PrepareOptions::check() const {
  if (!(time_scale > 0.0) || !(angle_scale > 0.0) || !std::isfinite(time_scale) ||
      !std::isfinite(angle_scale))
    throw InputError("the time and angle units must be positive");
  if (!std::isfinite(cutoff) || !std::isfinite(tau_cutoff))
    throw InputError("cutoff and tau_cutoff must be finite frequencies [Hz]");
  checkOption("prepare", "rate", rate, "rate");
  checkOption("prepare", "order", order, "order");
  checkOption("prepare", "decimate", decimate, "decimate");
  checkOption("prepare", "max-gap", max_gap, "max_gap");
  checkOption("prepare", "trim", trim, "trim");
  checkOption("prepare", "savgol-window", savgol_window, "savgol_window");
  checkOption("prepare", "savgol-degree", savgol_degree, "savgol_degree");
  checkOption("prepare", "validate-fraction", validate_fraction, "validate_fraction");
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
        "--keep-raw-torque keeps the held-out part's raw torques: hold a part out "
        "(--validate-fraction, --validate-time or --validate-runs)");
  checkOption("prepare", "joints", source.num_joints, "joints");
  checkOption("prepare", "threads", threads, "threads");
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
  Filters filters;
  for (const auto& [cutoff, option] :
       {std::pair{out.cutoff, "--cutoff"}, std::pair{out.tau_cutoff, "--tau-cutoff"}})
    if (cutoff > 0.0 && !(cutoff < out.rate / 2.0))
      throw InputError(std::string(option) + " " + formatNumber(cutoff) +
                       " Hz must be below the Nyquist frequency of the output rate (" +
                       formatNumber(out.rate / 2.0) + " Hz; --rate " + formatNumber(out.rate) +
                       ")");
  if (out.cutoff > 0.0) filters.q = butterworthLowPass(options.order, out.cutoff, out.rate);
  filters.tau_as_q = out.tau_cutoff == out.cutoff;
  if (out.tau_cutoff > 0.0 && !filters.tau_as_q)
    filters.tau = butterworthLowPass(options.order, out.tau_cutoff, out.rate);
  else if (filters.tau_as_q)
    filters.tau = filters.q;
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
