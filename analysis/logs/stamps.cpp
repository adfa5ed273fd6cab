#include "analysis/logs/prepare_steps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "analysis/logs/effort_scale.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid::prepare_steps {

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
    const std::string log = "the log (" + out.tau_file + ")";
    if (options.torque_constants.size() == 0)
      throw InputError("`torque_constants` has 0 values; " + log + " has " + std::to_string(n) +
                       " joints: give one per joint");
    const Eigen::VectorXd scale =
        effortScale(options.torque_constants, options.gear_ratios, n, log);
    for (int j = 0; j < n; ++j) out.setColumn(1 + n + j, out.column(1 + n + j) * scale[j]);
  } else if (options.torque_constants.size() > 0 || options.gear_ratios.size() > 0) {
    throw InputError("torque constants and gear ratios apply to motor currents (`current`)");
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
                             "separate files (prepare `log` a.csv b.csv) or raise `max_gap` to "
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

namespace {

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

}  // namespace

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

std::string resampleBoundMessage(double samples, double raw, double rate) {
  return "resampling at `rate` " + formatNumber(rate) + " Hz makes " + formatNumber(samples, 3) +
         " samples from " + formatNumber(raw, 3) + " logged ones; dynid prepares at most " +
         formatNumber(kMaxResampledSamples, 3) + " samples and " + formatNumber(kMaxUpsampling) +
         " per logged sample: lower `rate` (0: the log's median rate)";
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
                          double rate, int count, int first) {
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
      throw InputError("`rows` " + std::to_string(from) + ":" + std::to_string(to) + ": " + label +
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

namespace {

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

}  // namespace

std::string angleUnitMismatch(const std::vector<LogColumns>& files, double angle_scale) {
  const std::string given = angle_scale == 1.0 ? "rad" : "deg";
  for (const LogColumns& c : files)
    for (const auto* names : {&c.q, &c.dq})
      for (const std::string& name : *names) {
        const std::string named = angleUnitNamed(name);
        if (!named.empty() && named != given)
          return "the column '" + name + "' says " + (named == "deg" ? "degrees" : "radians") +
                 ", read as " + (given == "deg" ? "degrees" : "radians") + " (`angle_unit` " +
                 given + ")";
      }
  return "";
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
        "the motion: crop it with `window` " +
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

void alignToLogTime(RawSignals& s, const PrepareOptions& options, bool first, PrepareOutcome& out) {
  // Stamps from the log's first one: exact differences of the 64-bit stamps (epochs in ns).
  // Units per second as a whole number when it is one (ns: 1e9), so that a 1.7e18 ns epoch is
  // divided exactly rather than multiplied by the double nearest 1e-9 (off by 1e-7 s).
  const long double per_second = std::round(1.0L / static_cast<long double>(options.time_scale));
  const long double file_origin =
      std::abs(per_second * options.time_scale - 1.0L) < 1e-12L
          ? s.time_origin / per_second
          : s.time_origin * static_cast<long double>(options.time_scale);
  if (first) {  // the first file's earliest stamp (before any window) starts the log
    const double earliest = s.values.col(0).head(s.rows).minCoeff();
    out.time_origin = file_origin + earliest;
    s.values.col(0).head(s.rows).array() -= earliest;
  } else {
    s.values.col(0).head(s.rows).array() += static_cast<double>(file_origin - out.time_origin);
  }
}

std::string fewStampsMessage(const std::string& label, const PrepareOptions& options,
                             double spans_from, double spans_to) {
  std::string windows;
  for (const auto& [from, to] : options.windows)
    windows += (windows.empty() ? "" : ",") + formatNumber(from) + ":" + formatNumber(to);
  std::string message = label + ": fewer than 3 distinct time stamps";
  if (!options.windows.empty() || !options.row_windows.empty())
    message.append(" within ")
        .append(options.windows.empty() ? std::string("the `rows` given")
                                        : std::string("`window` ").append(windows))
        .append(" (the log spans ")
        .append(formatNumber(spans_from, 6))
        .append(" to ")
        .append(formatNumber(spans_to, 6))
        .append(" s from its first stamp)");
  return message;
}

void chooseRate(const std::string& first, const PrepareOptions& options, PrepareOutcome& out) {
  if (out.median_step > kSlowestStep || out.median_step < kFastestStep)
    throw InputError(
        first + ": the median step between time stamps is " + formatNumber(out.median_step, 4) +
        " s (" + formatNumber(1.0 / out.median_step, 4) + " Hz), " +
        (out.median_step > kSlowestStep
             ? "too slow to identify a robot's dynamics: if the stamps are not in seconds, give "
               "`time_unit` ms, us or ns"
             : "faster than robots log: are the stamps in a larger unit than `time_unit` says "
               "(seconds read as milliseconds)?"));
  if (options.rate > 0.0) {
    out.rate = options.rate;
    out.rate_reason = "given";
  } else {
    out.rate = nominalRate(1.0 / out.median_step, out.rate_reason);
  }
  out.max_gap = options.max_gap > 0.0 ? options.max_gap : 5.0 * out.median_step;
}

}  // namespace dynid::prepare_steps
