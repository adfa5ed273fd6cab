#include "analysis/prepare.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
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

RawSignals readSignals(const LogSource& source, const PrepareOptions& options) {
  RawSignals out;
  int n = source.num_joints;
  if (!source.table.empty()) {
    const RawTable table = readRawTable(source.table);
    const std::vector<int> q = selectColumns(table, source.q_columns, n > 0 ? n : -1, "q");
    n = static_cast<int>(q.size());
    const std::vector<int> t = selectColumns(table, source.time_column, 1, "time");
    const std::vector<int> tau = selectColumns(table, source.tau_columns, n, "tau");
    out.time = table.values.col(t[0]);
    out.q = table.values(Eigen::all, q);
    out.tau = table.values(Eigen::all, tau);
    if (!source.dq_columns.empty())
      out.dq = table.values(Eigen::all, selectColumns(table, source.dq_columns, n, "dq"));
  } else {
    if (n <= 0)
      throw InputError("give the number of joints (--joints) for one-file-per-signal logs");
    if (source.time_file.empty() || source.q_file.empty() || source.tau_file.empty())
      throw InputError("one-file-per-signal logs need the time, q and tau files");
    out.time = readValueFile(source.time_file, 1).col(0);
    out.q = readValueFile(source.q_file, n);
    out.tau = readValueFile(source.tau_file, n);
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

PrepareOutcome prepareLog(const LogSource& source, const PrepareOptions& options) {
  if (!(options.time_scale > 0.0) || !(options.angle_scale > 0.0))
    throw InputError("the time and angle units must be positive");
  if (options.decimate < 1) throw InputError("--decimate must be >= 1");
  if (!(options.validate_fraction >= 0.0 && options.validate_fraction < 1.0))
    throw InputError("the validation fraction must be in [0, 1)");
  RawSignals raw = readSignals(source, options);
  PrepareOutcome out;
  out.raw_samples = static_cast<int>(raw.time.size());
  if (out.raw_samples < 3) throw InputError("the log has fewer than 3 samples");
  const int n = static_cast<int>(raw.q.cols());

  // Sort by time (stable) and keep the first of each repeated stamp.
  std::vector<int> order(static_cast<std::size_t>(out.raw_samples));
  std::iota(order.begin(), order.end(), 0);
  for (int k = 1; k < out.raw_samples; ++k)
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
  const Eigen::VectorXd time = raw.time(kept);
  const Eigen::MatrixXd q = raw.q(kept, Eigen::all), tau = raw.tau(kept, Eigen::all);
  const bool has_dq = raw.dq.size() > 0;
  const Eigen::MatrixXd dq = has_dq ? Eigen::MatrixXd(raw.dq(kept, Eigen::all)) : Eigen::MatrixXd();
  if (time.size() < 3) throw InputError("the log has fewer than 3 distinct time stamps");
  std::vector<double> steps(static_cast<std::size_t>(time.size() - 1));
  for (Eigen::Index k = 0; k + 1 < time.size(); ++k) steps[k] = time[k + 1] - time[k];
  out.median_step = median(steps);
  out.min_step = *std::min_element(steps.begin(), steps.end());
  out.max_step = *std::max_element(steps.begin(), steps.end());
  out.rate = options.rate > 0.0 ? options.rate : 1.0 / out.median_step;
  out.max_gap = options.max_gap > 0.0 ? options.max_gap : 5.0 * out.median_step;
  out.cutoff = options.cutoff >= 0.0 ? options.cutoff : std::min(10.0, out.rate / 4.0);
  out.order = options.order;
  out.decimate = options.decimate;
  out.dq_derived = !has_dq || options.derive_dq;
  std::vector<Biquad> filter;
  if (out.cutoff > 0.0) filter = butterworthLowPass(options.order, out.cutoff, out.rate);
  out.trim = options.trim >= 0.0 ? options.trim : (out.cutoff > 0.0 ? 2.0 / out.cutoff : 0.0);

  // Runs: split where a step exceeds the gap limit.
  std::vector<std::pair<Eigen::Index, Eigen::Index>> runs;  // [begin, end)
  Eigen::Index begin = 0;
  for (Eigen::Index k = 0; k + 1 < time.size(); ++k)
    if (steps[k] > out.max_gap) {
      out.gaps.emplace_back(time[k], steps[k]);
      runs.emplace_back(begin, k + 1);
      begin = k + 1;
    }
  runs.emplace_back(begin, time.size());

  const double h = 1.0 / out.rate;
  Eigen::VectorXd noise_sum = Eigen::VectorXd::Zero(n);
  double noise_count = 0.0;
  for (const auto& [b, e] : runs) {
    PreparedRun run;
    run.start = time[b];
    run.end = time[e - 1];
    run.raw_samples = static_cast<int>(e - b);
    const int count = static_cast<int>(std::floor((run.end - run.start) * out.rate + 1e-9)) + 1;
    const int edge = static_cast<int>(std::ceil(out.trim * out.rate));
    // Enough samples for the filter's padding, the derivatives and the trimmed edges.
    if (count < std::max(2 * edge + 3, filter.empty() ? 3 : padTransient(filter) + 1)) {
      out.dropped_runs.push_back(run);
      continue;
    }
    const Eigen::VectorXd run_time = time.segment(b, e - b);
    Eigen::MatrixXd rq =
        resampleLinear(run_time, q.middleRows(b, e - b), run.start, out.rate, count);
    Eigen::MatrixXd rtau =
        resampleLinear(run_time, tau.middleRows(b, e - b), run.start, out.rate, count);
    Eigen::MatrixXd rdq =
        has_dq && !options.derive_dq
            ? resampleLinear(run_time, dq.middleRows(b, e - b), run.start, out.rate, count)
            : Eigen::MatrixXd();
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
    if (rdq.size() == 0) {
      rdq.resize(count, n);
      for (int j = 0; j < n; ++j) rdq.col(j) = derivative(rq.col(j), h);
    }
    for (int j = 0; j < n; ++j) rddq.col(j) = derivative(rdq.col(j), h);
    // Trim, decimate.
    std::vector<int> rows;
    for (int k = edge; k < count - edge; k += options.decimate) rows.push_back(k);
    Eigen::VectorXd out_time(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t k = 0; k < rows.size(); ++k)
      out_time[static_cast<Eigen::Index>(k)] = run.start + rows[k] * h;
    run.samples = static_cast<int>(rows.size());
    const auto take = [&](const Eigen::MatrixXd& m) {
      return Eigen::MatrixXd(m(rows, Eigen::all));
    };
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
  if (out.train.time.size() == 0)
    throw InputError("no sample left: every run is shorter than the filter's transient (" +
                     std::to_string(out.trim) + " s trimmed at each end); lower --trim or " +
                     "--max-gap's splitting, or raise --cutoff");
  out.tau_noise = noise_count > 0.0 ? Eigen::VectorXd((noise_sum / noise_count).cwiseSqrt())
                                    : Eigen::VectorXd::Zero(n);
  return out;
}

}  // namespace dynid
