#include "analysis/prepare.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <sstream>
#include <tuple>

#include "core/errors.hpp"
#include "core/signal.hpp"
#include "data/raw_log.hpp"

namespace dynid {

namespace {

/// The log as time plus one matrix per signal (rows = samples), in SI units.
struct RawSignals {
  Eigen::VectorXd time;
  Eigen::MatrixXd q, dq, tau;  // dq empty when not logged
};

/// One table's signals, or the per-signal files' when `table` is empty.
RawSignals readSignals(const LogSource& source, const std::string& table_path,
                       const PrepareOptions& options) {
  RawSignals out;
  int n = source.num_joints;
  std::string tau_file = table_path;
  if (!table_path.empty()) {
    const RawTable table = readRawTable(table_path);
    const std::vector<int> q = selectColumns(table, source.q_columns, n > 0 ? n : -1, "q");
    n = static_cast<int>(q.size());
    const std::vector<int> t = selectColumns(table, source.time_column, 1, "time");
    const std::vector<int> tau =
        selectColumns(table, source.tau_columns, n, source.current ? "current" : "tau");
    out.time = table.values.col(t[0]);
    out.q = table.values(Eigen::all, q);
    out.tau = table.values(Eigen::all, tau);
    if (!source.dq_columns.empty())
      out.dq = table.values(Eigen::all, selectColumns(table, source.dq_columns, n, "dq"));
  } else {
    if (n <= 0)
      throw InputError("give the number of joints (--joints) for one-file-per-signal logs");
    if (source.time_file.empty() || source.q_file.empty() || source.tau_file.empty())
      throw InputError("one-file-per-signal logs need the time, q and tau (or current) files");
    out.time = readValueFile(source.time_file, 1).col(0);
    out.q = readValueFile(source.q_file, n);
    out.tau = readValueFile(source.tau_file, n);
    tau_file = source.tau_file;
    if (!source.dq_file.empty()) out.dq = readValueFile(source.dq_file, n);
    const Eigen::Index samples = out.time.size();
    for (const auto& [name, m, file] :
         {std::tuple<const char*, const Eigen::MatrixXd*, const std::string*>{"q", &out.q,
                                                                              &source.q_file},
          {"tau", &out.tau, &source.tau_file},
          {"dq", &out.dq, &source.dq_file}})
      if (m->size() > 0 && m->rows() != samples)
        throw ParseError(*file, 0, name,
                         "has " + std::to_string(m->rows()) + " samples, the time file " +
                             std::to_string(samples));
  }
  out.time *= options.time_scale;
  out.q *= options.angle_scale;
  if (out.dq.size() > 0) out.dq *= options.angle_scale;
  if (source.current) {
    const Eigen::Index joints = out.q.cols();
    const auto check = [&](const Eigen::VectorXd& v, const char* what, bool required) {
      if (v.size() == 0 && !required) return;
      if (v.size() != joints)
        throw InputError(tau_file + ": motor currents need " + what +
                         " with one value per joint (" + std::to_string(joints) + "), got " +
                         std::to_string(v.size()));
      for (Eigen::Index j = 0; j < joints; ++j)
        if (!std::isfinite(v[j]) || v[j] == 0.0)
          throw InputError(std::string(what) + " of joint " + std::to_string(j + 1) +
                           " must be finite and non-zero");
    };
    check(options.torque_constants, "torque constants", true);
    check(options.gear_ratios, "gear ratios", false);
    Eigen::VectorXd scale = options.torque_constants;
    if (options.gear_ratios.size() > 0) scale = scale.cwiseProduct(options.gear_ratios);
    out.tau = out.tau * scale.asDiagonal();
  } else if (options.torque_constants.size() > 0 || options.gear_ratios.size() > 0) {
    throw InputError("torque constants and gear ratios apply to motor currents (--current)");
  }
  return out;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// Appends the rows of `block` (one per sample) as columns of `to`.
void appendSamples(Eigen::MatrixXd& to, const Eigen::MatrixXd& block) {
  const Eigen::Index old = to.cols();
  to.conservativeResize(block.cols(), old + block.rows());
  to.rightCols(block.rows()) = block.transpose();
}

void appendTrajectory(Trajectory& to, const Eigen::VectorXd& time, const Eigen::MatrixXd& q,
                      const Eigen::MatrixXd& dq, const Eigen::MatrixXd& ddq,
                      const Eigen::MatrixXd& tau) {
  const Eigen::Index old = to.time.size();
  to.time.conservativeResize(old + time.size());
  to.time.tail(time.size()) = time;
  appendSamples(to.q, q);
  appendSamples(to.dq, dq);
  appendSamples(to.ddq, ddq);
  appendSamples(to.tau, tau);
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

/// Sorts by time (stable) and keeps the first sample of each repeated stamp; counts both.
RawSignals sortAndDeduplicate(RawSignals raw, PrepareOutcome& out) {
  const auto samples = static_cast<int>(raw.time.size());
  std::vector<int> order(static_cast<std::size_t>(samples));
  std::iota(order.begin(), order.end(), 0);
  for (int k = 1; k < samples; ++k)
    if (raw.time[k] < raw.time[k - 1]) ++out.unsorted_stamps;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return raw.time[a] < raw.time[b]; });
  std::vector<int> kept;
  for (int k : order) {
    if (!kept.empty() && raw.time[k] == raw.time[kept.back()]) {
      ++out.repeated_stamps;
      continue;
    }
    kept.push_back(k);
  }
  RawSignals clean;
  clean.time = raw.time(kept);
  clean.q = raw.q(kept, Eigen::all);
  clean.tau = raw.tau(kept, Eigen::all);
  if (raw.dq.size() > 0) clean.dq = raw.dq(kept, Eigen::all);
  return clean;
}

bool sameSample(const RawSignals& s, Eigen::Index a, Eigen::Index b) {
  return s.q.row(a) == s.q.row(b) && s.tau.row(a) == s.tau.row(b) &&
         (s.dq.size() == 0 || s.dq.row(a) == s.dq.row(b));
}

/// Drops stalled repeats (PrepareOptions::keep_stalled): within each stretch of samples identical
/// to its first, the repeats go when the stretch ends within `max_gap` of its first stamp.
RawSignals dropStalled(RawSignals s, double max_gap, PrepareOutcome& out) {
  const Eigen::Index samples = s.time.size();
  std::vector<int> kept;
  Eigen::Index k = 0;
  while (k < samples) {
    Eigen::Index last = k;
    while (last + 1 < samples && sameSample(s, k, last + 1)) ++last;
    kept.push_back(static_cast<int>(k));
    const double bridged = (last + 1 < samples ? s.time[last + 1] : s.time[last]) - s.time[k];
    if (last > k && bridged <= max_gap) {
      out.stalled_repeats += static_cast<int>(last - k);
    } else {
      for (Eigen::Index r = k + 1; r <= last; ++r) kept.push_back(static_cast<int>(r));
    }
    k = last + 1;
  }
  if (static_cast<Eigen::Index>(kept.size()) == samples) return s;
  RawSignals out_signals;
  out_signals.time = s.time(kept);
  out_signals.q = s.q(kept, Eigen::all);
  out_signals.tau = s.tau(kept, Eigen::all);
  if (s.dq.size() > 0) out_signals.dq = s.dq(kept, Eigen::all);
  return out_signals;
}

std::vector<double> steps(const Eigen::VectorXd& time) {
  std::vector<double> out(static_cast<std::size_t>(std::max<Eigen::Index>(time.size() - 1, 0)));
  for (Eigen::Index k = 0; k + 1 < time.size(); ++k) out[k] = time[k + 1] - time[k];
  return out;
}

/// One run, resampled, filtered, differentiated, trimmed and decimated, appended to `out`'s
/// train and validate sets; dropped (recorded) when too short for the filter. `excerpt`: record
/// PrepareOutcome's excerpt from this run.
void prepareRun(const RawSignals& s, Eigen::Index b, Eigen::Index e, PreparedRun run,
                const std::vector<Biquad>& filter, const PrepareOptions& options, bool excerpt,
                Eigen::VectorXd& noise_sum, double& noise_count, PrepareOutcome& out) {
  const int n = static_cast<int>(s.q.cols());
  const double h = 1.0 / out.rate;
  run.start = s.time[b];
  run.end = s.time[e - 1];
  run.raw_samples = static_cast<int>(e - b);
  const int count = static_cast<int>(std::floor((run.end - run.start) * out.rate + 1e-9)) + 1;
  const int edge = static_cast<int>(std::ceil(out.trim * out.rate));
  // Enough samples for the filter's padding, the derivatives and the trimmed edges.
  if (count < std::max(2 * edge + 3, filter.empty() ? 3 : padTransient(filter) + 1)) {
    out.dropped_runs.push_back(run);
    return;
  }
  const Eigen::VectorXd run_time = s.time.segment(b, e - b);
  Eigen::MatrixXd rq =
      resampleLinear(run_time, s.q.middleRows(b, e - b), run.start, out.rate, count);
  Eigen::MatrixXd rtau =
      resampleLinear(run_time, s.tau.middleRows(b, e - b), run.start, out.rate, count);
  Eigen::MatrixXd rdq = out.dq_derived ? Eigen::MatrixXd()
                                       : resampleLinear(run_time, s.dq.middleRows(b, e - b),
                                                        run.start, out.rate, count);
  if (!filter.empty()) {
    for (int j = 0; j < n; ++j) {
      const Eigen::VectorXd filtered = filtfilt(filter, rtau.col(j));
      noise_sum[j] += (rtau.col(j) - filtered).squaredNorm();
      rtau.col(j) = filtered;
      rq.col(j) = filtfilt(filter, rq.col(j));
      if (rdq.size() > 0) rdq.col(j) = filtfilt(filter, rdq.col(j));
    }
    noise_count += count;
  }
  Eigen::MatrixXd rddq(count, n);
  const int window = std::min(out.savgol_window, count % 2 == 1 ? count : count - 1);
  const auto differentiate = [&](const Eigen::VectorXd& x, int order) {
    if (!options.savitzky_golay)
      return order == 1 ? derivative(x, h) : derivative(derivative(x, h), h);
    return savitzkyGolay(x, h, window, options.savgol_degree, order);
  };
  if (rdq.size() == 0) {
    rdq.resize(count, n);
    for (int j = 0; j < n; ++j) {
      rdq.col(j) = differentiate(rq.col(j), 1);
      // Savitzky-Golay: ddq from the same polynomials as dq; central differences: of dq.
      rddq.col(j) =
          options.savitzky_golay ? differentiate(rq.col(j), 2) : derivative(rdq.col(j), h);
    }
  } else {
    for (int j = 0; j < n; ++j) rddq.col(j) = differentiate(rdq.col(j), 1);
  }
  if (excerpt && !filter.empty()) {
    // 2 s (or the run) from its middle, before the trimming: what the filter did.
    const int length = std::min(count, static_cast<int>(std::lround(2.0 * out.rate)));
    const int first = (count - length) / 2;
    out.excerpt_time =
        Eigen::VectorXd::LinSpaced(length, run.start + run.time_offset + first * h,
                                   run.start + run.time_offset + (first + length - 1) * h);
    out.excerpt_raw =
        resampleLinear(run_time, s.tau.middleRows(b, e - b), run.start, out.rate, count)
            .middleRows(first, length);
    out.excerpt_filtered = rtau.middleRows(first, length);
  }
  // Trim, decimate.
  std::vector<int> rows;
  for (int k = edge; k < count - edge; k += options.decimate) rows.push_back(k);
  Eigen::VectorXd out_time(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k)
    out_time[static_cast<Eigen::Index>(k)] = run.start + run.time_offset + rows[k] * h;
  run.samples = static_cast<int>(rows.size());
  const auto take = [&](const Eigen::MatrixXd& m) { return Eigen::MatrixXd(m(rows, Eigen::all)); };
  const Eigen::MatrixXd oq = take(rq), odq = take(rdq), oddq = take(rddq), otau = take(rtau);
  const auto split = static_cast<Eigen::Index>(
      std::floor((1.0 - options.validate_fraction) * static_cast<double>(rows.size())));
  appendTrajectory(out.train, out_time.head(split), oq.topRows(split), odq.topRows(split),
                   oddq.topRows(split), otau.topRows(split));
  const Eigen::Index rest = out_time.size() - split;
  if (rest > 0)
    appendTrajectory(out.validate, out_time.tail(rest), oq.bottomRows(rest), odq.bottomRows(rest),
                     oddq.bottomRows(rest), otau.bottomRows(rest));
  out.runs.push_back(run);
}

/// Consecutive samples of one file without a gap.
struct RunSpan {
  std::size_t file = 0;
  Eigen::Index begin = 0, end = 0;  // [begin, end)
  PreparedRun run;                  // file and time offset set
};

int resampledCount(const RawSignals& s, const RunSpan& span, double rate) {
  return static_cast<int>(std::floor((s.time[span.end - 1] - s.time[span.begin]) * rate + 1e-9)) +
         1;
}

/// Spectra of q and tau over every run at least one segment long (each joint normalised to unit
/// power, then summed), the trajectory band and the noise edge.
void measureSpectra(const std::vector<RawSignals>& files, const std::vector<RunSpan>& spans,
                    PrepareOutcome& out) {
  int longest = 0;
  for (const RunSpan& span : spans)
    longest = std::max(longest, resampledCount(files[span.file], span, out.rate));
  // Resolution: segments of up to 16 s (a power of two), at least 64 samples.
  int segment = 64;
  while (2 * segment <= longest && 2 * segment <= 16.0 * out.rate) segment *= 2;
  if (longest < segment) return;
  const int n = static_cast<int>(files.front().q.cols());
  std::vector<Eigen::VectorXd> q_sum(static_cast<std::size_t>(n)), tau_sum(q_sum);
  for (const RunSpan& span : spans) {
    const RawSignals& s = files[span.file];
    const int count = resampledCount(s, span, out.rate);
    if (count < segment) continue;
    const Eigen::VectorXd time = s.time.segment(span.begin, span.end - span.begin);
    const double t0 = s.time[span.begin];
    const Eigen::MatrixXd rq = resampleLinear(
        time, s.q.middleRows(span.begin, span.end - span.begin), t0, out.rate, count);
    const Eigen::MatrixXd rtau = resampleLinear(
        time, s.tau.middleRows(span.begin, span.end - span.begin), t0, out.rate, count);
    // Weighted by the run's length: long runs dominate, as in one Welch average.
    const double weight = static_cast<double>(count);
    for (int j = 0; j < n; ++j) {
      const Spectrum sq = welchSpectrum(rq.col(j), out.rate, segment, 16);
      const Spectrum st = welchSpectrum(rtau.col(j), out.rate, segment, 16);
      if (q_sum[j].size() == 0) {
        q_sum[j] = Eigen::VectorXd::Zero(sq.density.size());
        tau_sum[j] = q_sum[j];
        out.q_spectrum.frequency = sq.frequency;
      }
      q_sum[j] += weight * sq.density;
      tau_sum[j] += weight * st.density;
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
  out.trajectory_band = f[std::min(band, d.size() - 1)];
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

std::string hz(double f) {
  std::ostringstream s;
  s.precision(3);
  s << f << " Hz";
  return s.str();
}

}  // namespace

PrepareOutcome prepareLog(const LogSource& source, const PrepareOptions& options) {
  if (!(options.time_scale > 0.0) || !(options.angle_scale > 0.0))
    throw InputError("the time and angle units must be positive");
  if (options.decimate < 1) throw InputError("--decimate must be >= 1");
  if (!(options.validate_fraction >= 0.0 && options.validate_fraction < 1.0))
    throw InputError("the validation fraction must be in [0, 1)");
  PrepareOutcome out;
  // Every file read, sorted and de-duplicated; the defaults from the median step over all.
  std::vector<RawSignals> files;
  std::vector<std::string> names = source.tables;
  if (names.empty()) names.push_back("");  // the per-signal files
  std::vector<double> all_steps;
  for (const std::string& name : names) {
    RawSignals raw = readSignals(source, name, options);
    out.raw_samples += static_cast<int>(raw.time.size());
    if (!files.empty() && raw.q.cols() != files.front().q.cols())
      throw InputError(name + ": " + std::to_string(raw.q.cols()) + " joints, the first log " +
                       std::to_string(files.front().q.cols()));
    files.push_back(sortAndDeduplicate(std::move(raw), out));
    const std::string label = name.empty() ? source.time_file : name;
    if (files.back().time.size() < 3)
      throw InputError(label + ": fewer than 3 distinct time stamps");
    const std::vector<double> s = steps(files.back().time);
    all_steps.insert(all_steps.end(), s.begin(), s.end());
  }
  out.median_step = median(all_steps);
  out.rate = options.rate > 0.0 ? options.rate : 1.0 / out.median_step;
  out.max_gap = options.max_gap > 0.0 ? options.max_gap : 5.0 * out.median_step;
  out.order = options.order;
  out.decimate = options.decimate;
  out.dq_derived = files.front().dq.size() == 0 || options.derive_dq;

  // Pass 1: stalls, steps, time offsets and the runs between gaps.
  out.min_step = std::numeric_limits<double>::infinity();
  std::vector<RunSpan> spans;
  double previous_end = -std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < files.size(); ++f) {
    RawSignals& signals = files[f];
    if (!options.keep_stalled) signals = dropStalled(std::move(signals), out.max_gap, out);
    if ((signals.dq.size() == 0) != (files.front().dq.size() == 0))
      throw InputError(names[f] + ": dq is logged in some files and not in others");
    const std::vector<double> s = steps(signals.time);
    out.min_step = std::min(out.min_step, *std::min_element(s.begin(), s.end()));
    out.max_step = std::max(out.max_step, *std::max_element(s.begin(), s.end()));
    RunSpan span;
    span.file = f;
    span.run.file = static_cast<int>(f);
    const double spacing = std::max(1.0, 2.0 * out.max_gap);
    if (signals.time[0] < previous_end + spacing && f > 0)
      span.run.time_offset = previous_end + spacing - signals.time[0];
    previous_end = signals.time[signals.time.size() - 1] + span.run.time_offset;
    for (Eigen::Index k = 0; k + 1 < signals.time.size(); ++k)
      if (s[k] > out.max_gap) {
        out.gaps.emplace_back(signals.time[k] + span.run.time_offset, s[k]);
        span.end = k + 1;
        spans.push_back(span);
        span.begin = k + 1;
      }
    span.end = signals.time.size();
    spans.push_back(span);
  }

  // Pass 2: the spectra, and the cutoff.
  measureSpectra(files, spans, out);
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
  std::vector<Biquad> filter;
  if (out.cutoff > 0.0) filter = butterworthLowPass(options.order, out.cutoff, out.rate);
  out.trim = options.trim >= 0.0 ? options.trim : (out.cutoff > 0.0 ? 2.0 / out.cutoff : 0.0);
  if (options.savitzky_golay) {
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
            : std::max(minimum,
                       2 * static_cast<int>(std::lround(out.rate / (8.0 * reference))) + 1);
  }

  // Pass 3: every run resampled, filtered, differentiated, trimmed and split.
  std::size_t longest = 0;
  for (std::size_t r = 0; r < spans.size(); ++r)
    if (spans[r].end - spans[r].begin > spans[longest].end - spans[longest].begin) longest = r;
  const int n = static_cast<int>(files.front().q.cols());
  Eigen::VectorXd noise_sum = Eigen::VectorXd::Zero(n);
  double noise_count = 0.0;
  for (std::size_t r = 0; r < spans.size(); ++r) {
    const RunSpan& span = spans[r];
    prepareRun(files[span.file], span.begin, span.end, span.run, filter, options, r == longest,
               noise_sum, noise_count, out);
    if (r + 1 == spans.size() || spans[r + 1].file != span.file)
      files[span.file] = RawSignals();  // done with this file
  }
  if (out.train.time.size() == 0)
    throw InputError("no sample left: every run is shorter than the filter's transient (" +
                     std::to_string(out.trim) + " s trimmed at each end); lower --trim or " +
                     "--max-gap's splitting, or raise --cutoff");
  out.tau_noise = noise_count > 0.0 ? Eigen::VectorXd((noise_sum / noise_count).cwiseSqrt())
                                    : Eigen::VectorXd::Zero(n);
  return out;
}

}  // namespace dynid
