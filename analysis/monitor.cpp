#include "analysis/monitor.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>

#include "analysis/logs/bag_log.hpp"
#include "analysis/records/document.hpp"
#include "analysis/runs.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/momentum.hpp"
#include "core/option_ranges.hpp"
#include "core/parallel.hpp"
#include "core/rnea.hpp"
#include "data/bags/bag.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"

namespace dynid {

// ---- the observer ----

MomentumObserver::MomentumObserver(const Model& model, const Eigen::VectorXd& gain)
    : model_(model), data_(model), gain_(gain) {
  const int n = model.numJoints();
  if (gain.size() != n || !gain.allFinite() || (gain.array() <= 0.0).any())
    throw InputError("the observer gain needs " + std::to_string(n) +
                     " entries, each > 0 and finite [1/s]");
  p0_ = integral_ = r_ = rate_ = Eigen::VectorXd::Zero(n);
}

const Eigen::VectorXd& MomentumObserver::update(double t,
                                                const Eigen::Ref<const Eigen::VectorXd>& q,
                                                const Eigen::Ref<const Eigen::VectorXd>& dq,
                                                const Eigen::Ref<const Eigen::VectorXd>& tau) {
  momentumTerms(model_, data_, q, dq, p_, beta_);
  if (!started_) {
    // r = 0 at the start: the observer assumes no external torque then.
    p0_ = p_;
    integral_.setZero();
    r_.setZero();
    rate_ = tau - beta_;
    t_ = t;
    started_ = true;
    return r_;
  }
  const double dt = t - t_;
  assert(dt > 0.0);
  // Trapezoid: I_k = I_{k-1} + dt/2 (u_{k-1} + r_{k-1} + u_k + r_k), r_k = K (p_k - p0 - I_k),
  // solved for r_k.
  const Eigen::VectorXd u = tau - beta_;
  const Eigen::ArrayXd half = 0.5 * dt * gain_.array();
  const Eigen::VectorXd known = integral_ + 0.5 * dt * (rate_ + u);
  r_ = (gain_.array() * (p_ - p0_ - known).array() / (1.0 + half)).matrix();
  integral_ = known + 0.5 * dt * r_;
  rate_ = u + r_;
  t_ = t;
  return r_;
}

// ---- statistics and thresholds ----

void ResidualStatistics::reset(int n, double block_seconds) {
  sum_squares = rate_sum_squares = max_abs = Eigen::VectorXd::Zero(n);
  block_max = block_sum = block_sum_squares = Eigen::VectorXd::Zero(n);
  rate_time = 0.0;
  block = block_seconds;
  blocks = 0;
  samples = 0;
}

void ResidualStatistics::add(double t, const Eigen::VectorXd& r, const Eigen::VectorXd* previous,
                             double dt) {
  sum_squares += r.cwiseAbs2();
  max_abs = max_abs.cwiseMax(r.cwiseAbs());
  if (samples == 0) block_start = t;
  if (t - block_start >= block) {  // the block is complete: its maximum joins the others
    block_sum += block_max;
    block_sum_squares += block_max.cwiseAbs2();
    ++blocks;
    block_max.setZero();
    block_start += block * std::floor((t - block_start) / block);
  }
  block_max = block_max.cwiseMax(r.cwiseAbs());
  ++samples;
  if (previous && dt > 0.0) {
    rate_sum_squares += (r - *previous).cwiseAbs2() / dt;  // (dr/dt)^2 dt
    rate_time += dt;
  }
}

Eigen::VectorXd ResidualStatistics::rms() const {
  return samples > 0 ? Eigen::VectorXd((sum_squares / static_cast<double>(samples)).cwiseSqrt())
                     : Eigen::VectorXd::Zero(sum_squares.size());
}

Eigen::VectorXd ResidualStatistics::rateRms() const {
  return rate_time > 0.0 ? Eigen::VectorXd((rate_sum_squares / rate_time).cwiseSqrt())
                         : Eigen::VectorXd::Zero(sum_squares.size());
}

Eigen::VectorXd riceThresholds(const ResidualStatistics& statistics, double rate) {
  const Eigen::VectorXd s = statistics.rms(), ds = statistics.rateRms();
  Eigen::VectorXd out(s.size());
  for (Eigen::Index j = 0; j < s.size(); ++j) {
    double u = 0.0;
    if (s[j] > 0.0 && ds[j] > 0.0) {
      const double ratio = ds[j] / (std::numbers::pi * s[j] * rate);
      u = s[j] * std::sqrt(2.0 * std::log(std::max(ratio, 1.0)));
    }
    double gumbel = 0.0;
    if (statistics.blocks >= 10) {
      const double m = statistics.blocks;
      const double mean = statistics.block_sum[j] / m;
      const double sd = std::sqrt(std::max(0.0, statistics.block_sum_squares[j] / m - mean * mean) *
                                  m / (m - 1.0));
      const double beta = sd * std::sqrt(6.0) / std::numbers::pi;
      const double mu = mean - 0.5772156649015329 * beta;
      const double p = std::min(rate * statistics.block, 0.5);
      gumbel = mu - beta * std::log(-std::log1p(-p));
    }
    out[j] = std::max({u, gumbel, statistics.max_abs[j]});
  }
  return out;
}

// ---- the envelope ----

void ResidualEnvelope::reset(int n) {
  time_.resize(2 * kMaxBuckets);
  low_.resize(n, 2 * kMaxBuckets);
  high_.resize(n, 2 * kMaxBuckets);
  count_ = 0, stride_ = 1, in_bucket_ = 0;
}

void ResidualEnvelope::add(double t, const Eigen::VectorXd& r) {
  if (in_bucket_ == 0) {
    if (count_ == 2 * kMaxBuckets) {
      // Merge neighbouring buckets: the stride doubles, the envelope stays the same.
      for (int b = 0; b < kMaxBuckets; ++b) {
        time_[b] = time_[2 * b];
        low_.col(b) = low_.col(2 * b).cwiseMin(low_.col(2 * b + 1));
        high_.col(b) = high_.col(2 * b).cwiseMax(high_.col(2 * b + 1));
      }
      count_ = kMaxBuckets;
      stride_ *= 2;
    }
    time_[count_] = t;
    low_.col(count_) = r;
    high_.col(count_) = r;
    ++count_;
  } else {
    low_.col(count_ - 1) = low_.col(count_ - 1).cwiseMin(r);
    high_.col(count_ - 1) = high_.col(count_ - 1).cwiseMax(r);
  }
  in_bucket_ = (in_bucket_ + 1) % stride_;
}

// ---- streamed samples ----

namespace {
double parseField(std::string_view field, const std::string& source, long long line,
                  const std::string& column) {
  while (!field.empty() && (field.front() == ' ' || field.front() == '\t')) field.remove_prefix(1);
  while (!field.empty() && (field.back() == ' ' || field.back() == '\t' || field.back() == '\r'))
    field.remove_suffix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (field.empty() || error != std::errc() || end != field.data() + field.size())
    throw ParseError(source, static_cast<int>(std::min<long long>(line, INT32_MAX)), column,
                     "not a number: '" + std::string(field.substr(0, 40)) + "'");
  if (!std::isfinite(value))
    throw ParseError(source, static_cast<int>(std::min<long long>(line, INT32_MAX)), column,
                     "not a finite number");
  return value;
}

std::vector<std::string> sampleColumns(int n, bool with_ddq) {
  std::vector<std::string> out{"t"};
  for (const char* prefix : {"q", "dq", "ddq", "tau"}) {
    if (!with_ddq && std::string(prefix) == "ddq") continue;
    for (int j = 1; j <= n; ++j) out.push_back(prefix + std::to_string(j));
  }
  return out;
}

std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= line.size(); ++i)
    if (i == line.size() || line[i] == ',') {
      out.push_back(line.substr(start, i - start));
      start = i + 1;
    }
  return out;
}
}  // namespace

bool parseSampleHeader(const std::string& line, int n, const std::string& source) {
  std::vector<std::string_view> fields = splitFields(line);
  for (auto& f : fields)
    while (!f.empty() && (f.back() == '\r' || f.back() == ' ')) f.remove_suffix(1);
  const bool with_ddq = static_cast<int>(fields.size()) == 4 * n + 1;
  const std::vector<std::string> expected = sampleColumns(n, with_ddq);
  for (std::size_t c = 0; c < std::max(expected.size(), fields.size()); ++c) {
    if (c < fields.size() && c < expected.size() && fields[c] == expected[c]) continue;
    throw ParseError(source, 1, c < expected.size() ? expected[c] : std::string(fields[c]),
                     "the header must be t,q1..q" + std::to_string(n) + ",dq1..dq" +
                         std::to_string(n) + ",tau1..tau" + std::to_string(n) +
                         " (or the dataset header with ddq1..ddq" + std::to_string(n) +
                         ") for this " + std::to_string(n) + "-joint robot; column " +
                         std::to_string(c + 1) + " differs");
  }
  return with_ddq;
}

void parseSampleLine(const std::string& line, int n, bool with_ddq, const std::string& source,
                     long long line_number, double& t, Eigen::VectorXd& q, Eigen::VectorXd& dq,
                     Eigen::VectorXd& ddq, Eigen::VectorXd& tau) {
  const std::vector<std::string_view> fields = splitFields(line);
  const std::vector<std::string> columns = sampleColumns(n, with_ddq);
  if (fields.size() != columns.size())
    throw ParseError(source, static_cast<int>(std::min<long long>(line_number, INT32_MAX)), "",
                     std::to_string(fields.size()) + " fields, the header has " +
                         std::to_string(columns.size()));
  std::size_t c = 0;
  auto next = [&] {
    const double v = parseField(fields[c], source, line_number, columns[c]);
    ++c;
    return v;
  };
  t = next();
  q.resize(n), dq.resize(n), ddq.resize(n), tau.resize(n);
  for (int j = 0; j < n; ++j) q[j] = next();
  for (int j = 0; j < n; ++j) dq[j] = next();
  if (with_ddq)
    for (int j = 0; j < n; ++j) ddq[j] = next();
  for (int j = 0; j < n; ++j) tau[j] = next();
}

// ---- the request ----

void MonitorRequest::check() const {
  if (calibration_file.empty() == thresholds_file.empty())
    throw InputError(
        "give the thresholds' source: --calibration CLEAN.csv (a log without contact) or "
        "--thresholds thresholds.json (a monitor's earlier output), exactly one of them");
  checkOption("monitor", "false-alarms-per-hour", false_alarms_per_hour, "--false-alarms-per-hour");
  checkOption("monitor", "hold", hold, "--hold");
  checkOption("monitor", "max-gap", max_gap, "--max-gap");
  if (gain && (!gain->allFinite() || (gain->array() <= 0.0).any() || (gain->array() > 1e6).any()))
    throw InputError("--gain: each value must be > 0 and at most 1e6 [1/s]");
  // How a recording is read means nothing for a dataset CSV or stdin: refused, not ignored.
  const bool recording =
      bags::isBag(data_file) || (!calibration_file.empty() && bags::isBag(calibration_file));
  if (!recording && (!topic.empty() || !effort_topic.empty() || !joint_prefix.empty() ||
                     !joint_names.empty() || receive_time))
    throw InputError(
        "--topic, --stamp receive, --effort-topic, --joint-prefix and --joint-names apply to "
        "recordings (.mcap, .db3, .bag, bag directories), and neither " +
        data_file + " nor the calibration is one");
}

namespace {

/// Per joint, what a raw effort is multiplied by to give the joint torque: torque constant x gear
/// ratio with currents, else empty (the efforts are torques). Throws InputError for a count other
/// than the robot's joints, or a value that is zero or not finite.
Eigen::VectorXd effortScale(const MonitorRequest& request, int n) {
  if (request.torque_constants.size() == 0) {
    if (request.gear_ratios.size() > 0)
      throw InputError("--gear-ratios applies to motor currents: give --torque-constants too");
    return {};
  }
  for (const auto& [v, what] : {std::pair{&request.torque_constants, "--torque-constants"},
                                std::pair{&request.gear_ratios, "--gear-ratios"}}) {
    if (v->size() == 0) continue;
    if (v->size() != n)
      throw InputError(std::string(what) + " has " + std::to_string(v->size()) +
                       " values; the robot has " + std::to_string(n) +
                       " joints: give one per joint");
    for (Eigen::Index j = 0; j < n; ++j)
      if (!std::isfinite((*v)[j]) || (*v)[j] == 0.0)
        throw InputError(std::string(what) + ": the value of joint " + std::to_string(j + 1) +
                         " must be finite and non-zero");
  }
  Eigen::VectorXd scale = request.torque_constants;
  if (request.gear_ratios.size() > 0) scale.array() *= request.gear_ratios.array();
  return scale;
}

/// Whether `file` holds raw efforts (a recording, or stdin), which --torque-constants scales.
bool rawEfforts(const std::string& file) { return file == "-" || bags::isBag(file); }

/// An estimate identified from motor currents monitoring raw efforts: a warning when no torque
/// constants are given (the efforts are taken as torques, and if they are currents every residual
/// is in another unit), or when they differ from the estimate's.
void currentsWarning(const LoadedArm& arm, const MonitorRequest& request,
                     const Eigen::VectorXd& mine, std::vector<std::string>& warnings) {
  if (arm.torque_constants.empty()) return;
  const auto list = [](const std::vector<double>& v) {
    std::string out;
    for (double x : v) {
      if (!out.empty()) out += ',';
      out += formatNumber(x, 6);
    }
    return out;
  };
  const std::string given =
      "--torque-constants " + list(arm.torque_constants) +
      (arm.gear_ratios.empty() ? "" : " --gear-ratios " + list(arm.gear_ratios));
  if (request.torque_constants.size() == 0) {
    warnings.push_back(request.arm +
                       " was identified from motor currents converted to torques (dynid prepare " +
                       given +
                       "); the recording's efforts are taken as joint torques [N m]. If they are "
                       "currents, give the same: " +
                       given);
    return;
  }
  // What matters is the product, current x constant x ratio.
  Eigen::VectorXd theirs = Eigen::Map<const Eigen::VectorXd>(
      arm.torque_constants.data(), static_cast<Eigen::Index>(arm.torque_constants.size()));
  for (std::size_t j = 0; j < arm.gear_ratios.size() && j < arm.torque_constants.size(); ++j)
    theirs[static_cast<Eigen::Index>(j)] *= arm.gear_ratios[j];
  if (mine.size() != theirs.size() ||
      ((mine - theirs).array().abs() > 1e-9 * theirs.array().abs()).any())
    warnings.push_back("the torque constants and gear ratios given differ from those " +
                       request.arm + " was identified with (" + given +
                       "): the residuals then carry the difference");
}

/// Whether the residuals are above their thresholds, and the event they make.
class EventDetector {
 public:
  EventDetector(const Eigen::VectorXd& thresholds, double hold, MonitorEventSink* sink,
                std::vector<MonitorEvent>& events)
      : thresholds_(thresholds), hold_(hold), sink_(sink), events_(events) {}

  void add(double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd& dq) {
    const Eigen::ArrayXd ratio = r.cwiseAbs().array() / thresholds_.array();
    const bool above = (ratio > 1.0).any();
    if (!active_) {
      if (!above) return;
      event_ = MonitorEvent{};
      event_.start = event_.end = t;
      active_ = true;
      mark(t, r, ratio);
      if (sink_) sink_->started(event_);
      return;
    }
    event_.energy += r.dot(dq) * dt;
    if (above) {
      mark(t, r, ratio);
      event_.end = t;
      quiet_since_.reset();
      return;
    }
    if (!quiet_since_) quiet_since_ = t;
    if (t - *quiet_since_ >= hold_) finish(false);
  }
  /// The data ended (or were stopped) during an event.
  void close() {
    if (active_) finish(true);
  }

 private:
  void mark(double t, const Eigen::VectorXd& r, const Eigen::ArrayXd& ratio) {
    for (Eigen::Index j = 0; j < r.size(); ++j) {
      if (ratio[j] > 1.0 &&
          std::find(event_.joints.begin(), event_.joints.end(), j) == event_.joints.end())
        event_.joints.push_back(static_cast<int>(j));
      if (std::abs(r[j]) > event_.peak) {
        event_.peak = std::abs(r[j]);
        event_.peak_joint = static_cast<int>(j);
        event_.peak_time = t;
      }
    }
  }
  void finish(bool open) {
    event_.open = open;
    std::sort(event_.joints.begin(), event_.joints.end());
    events_.push_back(event_);
    if (sink_) sink_->ended(event_);
    active_ = false;
    quiet_since_.reset();
  }
  const Eigen::VectorXd& thresholds_;
  double hold_;
  MonitorEventSink* sink_;
  std::vector<MonitorEvent>& events_;
  bool active_ = false;
  std::optional<double> quiet_since_;
  MonitorEvent event_;
};

/// One pass over a log: the observer (and the direct residual where ddq is given) at every
/// sample, handed to `visit(t, dt, r_observer, r_direct or null, dq)`; dt = 0 after a restart.
struct Pass {
  long long samples = 0;
  double first = 0.0, last = 0.0;
  int restarts = 0;
  bool has_direct = false;
  bool interrupted = false;
};

using Visit = std::function<void(double t, double dt, const Eigen::VectorXd& observer,
                                 const Eigen::VectorXd* direct, const Eigen::VectorXd& dq)>;

Pass passOverFile(const Model& model, const std::string& file, const Eigen::VectorXd& gain,
                  double max_gap, int threads, const RunControl& control, const Visit& visit) {
  const int n = model.numJoints();
  DatasetReader reader(file, -1);
  if (reader.numJoints() != n)
    throw InputError(file + ": a log of " + std::to_string(reader.numJoints()) +
                     " joints, the robot '" + model.name + "' has " + std::to_string(n) +
                     ": a log of another robot?");
  ThreadPool pool(threads);
  std::vector<Data> data(static_cast<std::size_t>(pool.numThreads()), Data(model));
  MomentumObserver observer(model, gain);
  Trajectory chunk;
  Eigen::MatrixXd direct;
  Pass out;
  out.has_direct = true;
  double previous = 0.0;
  while (const int count = reader.read(chunk, 4096, &pool)) {
    // The direct residuals tau - RNEA(q, dq, ddq), on every thread.
    direct.resize(n, count);
    pool.parallelFor(count, [&](int k, int thread) {
      direct.col(k) = chunk.tau.col(k) - rnea(model, data[static_cast<std::size_t>(thread)],
                                              chunk.q.col(k), chunk.dq.col(k), chunk.ddq.col(k));
    });
    for (int k = 0; k < count; ++k) {
      if (control.stopped()) {  // Ctrl-C: after this sample, not this chunk
        out.interrupted = true;
        return out;
      }
      const double t = chunk.time[k];
      double dt = out.samples > 0 ? t - previous : 0.0;
      if (dt > max_gap) {
        observer.restart();
        ++out.restarts;
        dt = 0.0;
      }
      const Eigen::VectorXd& r =
          observer.update(t, chunk.q.col(k), chunk.dq.col(k), chunk.tau.col(k));
      const Eigen::VectorXd d = direct.col(k);
      visit(t, dt, r, &d, chunk.dq.col(k));
      if (out.samples == 0) out.first = t;
      out.last = previous = t;
      ++out.samples;
    }
    if (control.check()) {
      out.interrupted = true;
      break;
    }
  }
  return out;
}

Pass passOverStream(const Model& model, const MonitorRequest& request, const Eigen::VectorXd& gain,
                    const Visit& visit) {
  const int n = model.numJoints();
  const std::string source = "<stdin>";
  std::string line;
  if (!request.next_line || !request.next_line(line))
    throw ParseError(source, 1, "", "no header: the stream ended before its first line");
  const bool with_ddq = parseSampleHeader(line, n, source);
  const Eigen::VectorXd scale = effortScale(request, n);
  MomentumObserver observer(model, gain);
  Data data(model);
  Pass out;
  out.has_direct = with_ddq;
  double t = 0.0, previous = 0.0;
  Eigen::VectorXd q, dq, ddq, tau, direct;
  long long number = 1;
  while (true) {
    if (request.control.check()) {
      out.interrupted = true;
      break;
    }
    if (!request.next_line(line)) {
      out.interrupted = request.control.stopped();  // a reader gives up its wait on Ctrl-C
      break;
    }
    ++number;
    parseSampleLine(line, n, with_ddq, source, number, t, q, dq, ddq, tau);
    if (scale.size() > 0) tau.array() *= scale.array();  // currents to torques
    if (out.samples > 0 && !(t > previous))
      throw ParseError(source, static_cast<int>(std::min<long long>(number, INT32_MAX)), "t",
                       "time must increase (previous sample at " + std::to_string(previous) + ")");
    double dt = out.samples > 0 ? t - previous : 0.0;
    if (dt > request.max_gap) {
      observer.restart();
      ++out.restarts;
      dt = 0.0;
    }
    const Eigen::VectorXd& r = observer.update(t, q, dq, tau);
    if (with_ddq) direct = tau - rnea(model, data, q, dq, ddq);
    visit(t, dt, r, with_ddq ? &direct : nullptr, dq);
    if (out.samples == 0) out.first = t;
    out.last = previous = t;
    ++out.samples;
  }
  return out;
}

constexpr const char* kDirectNeedsDdq =
    "a recording has no ddq, and --residual direct needs it: use the observer, or prepare the "
    "recording (dynid prepare) and monitor the dataset";

/// How long after a later-stamped message a recording's message may come and still be put in
/// order [s]: a recorder stores messages as it receives them, and header stamps can lag that.
constexpr double kReorderWindow = 1.0;

/// Feeds a recording's samples, in time order, to the observer and `visit`.
class RecordingFeed {
 public:
  RecordingFeed(const Model& model, const std::string& path, const MonitorRequest& request,
                const Eigen::VectorXd& gain, const Visit& visit, Pass& out)
      : model_(model),
        path_(path),
        request_(request),
        visit_(visit),
        out_(out),
        observer_(model, gain),
        scale_(effortScale(request, model.numJoints())) {}
  /// One sample at t [s from the first]: q, tau, dq (n each) from `row`.
  void add(double t, const double* row, long long message) {
    const int n = model_.numJoints();
    q_ = Eigen::Map<const Eigen::VectorXd>(row, n);
    tau_ = Eigen::Map<const Eigen::VectorXd>(row + n, n);
    dq_ = Eigen::Map<const Eigen::VectorXd>(row + 2 * n, n);
    for (const auto& [name, v] : {std::pair<const char*, const Eigen::VectorXd*>{"position", &q_},
                                  {"velocity", &dq_},
                                  {"effort", &tau_}})
      for (int j = 0; j < n; ++j)
        if (!std::isfinite((*v)[j]))
          throw InputError(path_ + ": the JointState message at " + formatNumber(t, 9) +
                           " s (message " + std::to_string(message) + " as recorded) has a " +
                           name + " of joint " + model_.joint_names[static_cast<std::size_t>(j)] +
                           " that is not finite");
    if (scale_.size() > 0) tau_.array() *= scale_.array();  // currents to torques
    double dt = out_.samples > 0 ? t - out_.last : 0.0;
    if (dt > request_.max_gap) {
      observer_.restart();
      ++out_.restarts;
      dt = 0.0;
    }
    const Eigen::VectorXd& r = observer_.update(t, q_, dq_, tau_);
    visit_(t, dt, r, nullptr, dq_);
    if (out_.samples == 0) out_.first = t;
    out_.last = t;
    ++out_.samples;
  }

 private:
  const Model& model_;
  const std::string& path_;
  const MonitorRequest& request_;
  const Visit& visit_;
  Pass& out_;
  MomentumObserver observer_;
  Eigen::VectorXd scale_;  // effortScale's
  Eigen::VectorXd q_, tau_, dq_;
};

std::string noVelocities(const std::string& path) {
  return path +
         ": its JointState messages carry no velocities, and the observer needs dq: prepare the "
         "recording first (dynid prepare --log " +
         path + " --robot ROBOT --out DIR) and monitor DIR/train.csv";
}

/// A recording's JointState samples at their own stamps, in time order: raw, as a monitor beside
/// the robot sees them (no resampling or filtering; the observer needs no derivative of them).
/// Streamed in constant memory through a reorder window of kReorderWindow; with efforts on another
/// topic, read whole (the efforts are interpolated at the positions' stamps).
Pass passOverRecording(const Model& model, const std::string& path, const MonitorRequest& request,
                       const Eigen::VectorXd& gain, const Visit& visit,
                       std::vector<std::string>& warnings) {
  const int n = model.numJoints();
  LogSource source;
  source.tables = {path};
  source.topic = request.topic;
  source.effort_topic = request.effort_topic;
  source.receive_time = request.receive_time;
  source.joint_names = request.joint_names.empty() ? model.joint_names : request.joint_names;
  if (static_cast<int>(source.joint_names.size()) != n)
    throw InputError("the joint names given (--joint-names) are " +
                     std::to_string(source.joint_names.size()) + ", the arm has " +
                     std::to_string(n) + " joints");
  source.joint_prefix = request.joint_prefix;
  Pass out;
  RecordingFeed feed(model, path, request, gain, visit, out);
  long long skipped = 0;
  if (!request.effort_topic.empty()) {
    const RawSignals raw = readBagLog(source, path);
    if (!raw.has_dq) throw InputError(noVelocities(path));
    for (const std::string& w : raw.warnings) warnings.push_back(path + ": " + w);
    std::vector<Eigen::Index> order(static_cast<std::size_t>(raw.rows));
    for (Eigen::Index k = 0; k < raw.rows; ++k) order[static_cast<std::size_t>(k)] = k;
    std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
      return raw.values(a, 0) < raw.values(b, 0);
    });
    const double origin = raw.values(order.front(), 0);
    Eigen::VectorXd row(3 * n);
    for (std::size_t i = 0; i < order.size() && !out.interrupted; ++i) {
      if ((i % 4096 == 0 && request.control.check()) || request.control.stopped()) {
        out.interrupted = true;
        break;
      }
      const Eigen::Index k = order[i];
      const double t = raw.values(k, 0) - origin;
      if (out.samples > 0 && !(t > out.last)) {
        ++skipped;
        continue;
      }
      row = raw.values.block(k, 1, 1, 3 * n).transpose();
      feed.add(t, row.data(), k + 1);
    }
  } else {
    struct Pending {
      std::int64_t ns;
      long long message;
      std::vector<double> row;
    };
    struct Stopped {};
    std::deque<Pending> pending;  // by stamp
    std::int64_t newest = 0, origin = 0, last = 0;
    const auto window = static_cast<std::int64_t>(kReorderWindow * 1e9);
    long long message = 0;
    const auto emit = [&] {
      if (request.control.stopped()) throw Stopped{};  // after the sample that set it
      const Pending& p = pending.front();
      if (out.samples == 0) origin = p.ns;
      last = p.ns;
      feed.add(static_cast<double>(p.ns - origin) * 1e-9, p.row.data(), p.message);
      pending.pop_front();
    };
    try {
      const JointStateScan scan =
          scanJointStates(source, path, [&](std::int64_t ns, const std::vector<double>& row) {
            ++message;
            if (row.size() != static_cast<std::size_t>(3 * n)) throw InputError(noVelocities(path));
            if ((message % 4096 == 0 && request.control.check()) || request.control.stopped())
              throw Stopped{};
            const auto at =
                std::upper_bound(pending.begin(), pending.end(), ns,
                                 [](std::int64_t v, const Pending& p) { return v < p.ns; });
            if ((out.samples > 0 && ns <= last) || (at != pending.begin() && (at - 1)->ns == ns)) {
              ++skipped;  // a stamp already seen, or later than the window allows
              return;
            }
            pending.insert(at, Pending{ns, message, row});
            newest = message == 1 ? ns : std::max(newest, ns);
            while (!pending.empty() && pending.front().ns < newest - window) emit();
          });
      while (!pending.empty()) emit();
      if (const std::string w = prefixWarning(scan); !w.empty())
        warnings.push_back(path + ": " + w);
    } catch (const Stopped&) {
      out.interrupted = true;
    }
  }
  if (skipped > 0)
    warnings.push_back(path + ": " + std::to_string(skipped) +
                       " message(s) repeated an earlier stamp (or came more than " +
                       formatNumber(kReorderWindow) +
                       " s after later-stamped ones) and were skipped");
  return out;
}

/// One pass over a dataset CSV or a recording (by its name: data/bags/bag.hpp's isBag).
Pass passOverLog(const Model& model, const std::string& file, const MonitorRequest& request,
                 const Eigen::VectorXd& gain, const Visit& visit,
                 std::vector<std::string>& warnings) {
  if (bags::isBag(file)) return passOverRecording(model, file, request, gain, visit, warnings);
  return passOverFile(model, file, gain, request.max_gap, request.threads, request.control, visit);
}

/// The ground truth's episodes: runs of samples where any applied torque is nonzero.
std::vector<std::pair<double, double>> truthEpisodes(const std::string& file, int n) {
  LineReader lines(file);
  std::string_view view;
  if (!lines.next(view)) throw ParseError(file, 1, "", "empty: expected t,tau_ext1..");
  std::string header(view);
  std::vector<std::string_view> fields = splitFields(header);
  if (static_cast<int>(fields.size()) != n + 1 || fields[0] != "t")
    throw ParseError(file, 1, "",
                     "expected the header t,tau_ext1..tau_ext" + std::to_string(n) +
                         " (dynid simulate --disturbance's ground truth)");
  std::vector<std::pair<double, double>> out;
  bool in = false;
  double start = 0.0, last = 0.0;
  while (lines.next(view)) {
    const std::vector<std::string_view> row = splitFields(view);
    if (row.size() == 1 && row[0].empty()) continue;
    if (static_cast<int>(row.size()) != n + 1)
      throw ParseError(file, lines.lineNumber(), "",
                       std::to_string(row.size()) + " fields, expected " + std::to_string(n + 1));
    const double t = parseField(row[0], file, lines.lineNumber(), "t");
    bool any = false;
    for (int j = 1; j <= n; ++j)
      any =
          any || parseField(row[j], file, lines.lineNumber(), "tau_ext" + std::to_string(j)) != 0.0;
    if (any && !in) start = t, in = true;
    if (!any && in) out.emplace_back(start, last), in = false;
    last = t;
  }
  if (in) out.emplace_back(start, last);
  return out;
}

TruthScore scoreEvents(const std::vector<std::pair<double, double>>& episodes,
                       const std::vector<MonitorEvent>& events) {
  TruthScore out;
  out.episodes = static_cast<int>(episodes.size());
  for (const auto& episode : episodes) {
    // (Not a structured binding: clang 14 cannot capture one in a lambda.)
    const double start = episode.first, end = episode.second;
    const auto hit = std::find_if(events.begin(), events.end(), [&](const MonitorEvent& e) {
      return e.start >= start && e.start <= end + out.window;
    });
    if (hit != events.end() && hit->start <= start + out.window) {
      ++out.detected;
      out.delays.push_back(hit->start - start);
    } else {
      out.missed_starts.push_back(start);
    }
  }
  for (const MonitorEvent& e : events) {
    const bool explained = std::any_of(episodes.begin(), episodes.end(), [&](const auto& ep) {
      return e.end >= ep.first && e.start <= ep.second + out.window;
    });
    if (!explained) ++out.false_alarms;
  }
  return out;
}

MonitorThresholds calibrate(const Model& model, const MonitorRequest& request,
                            const Eigen::VectorXd& gain, std::vector<std::string>& warnings) {
  const int n = model.numJoints();
  ResidualStatistics stats;
  stats.reset(n);
  Eigen::VectorXd previous;
  const bool direct = request.residual == MonitorResidual::kDirect;
  const Pass pass = passOverLog(
      model, request.calibration_file, request, gain,
      [&](double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd* d,
          const Eigen::VectorXd&) {
        if (direct && !d) throw InputError(request.calibration_file + ": " + kDirectNeedsDdq);
        const Eigen::VectorXd& x = direct ? *d : r;
        stats.add(t, x, dt > 0.0 ? &previous : nullptr, dt);
        previous = x;
      },
      warnings);
  if (pass.interrupted) throw InputError("stopped during the calibration: no thresholds");
  MonitorThresholds out;
  out.robot = model.name;
  out.joint_names = model.joint_names;
  out.residual = request.residual;
  out.gain = gain;
  out.false_alarms_per_hour = request.false_alarms_per_hour;
  out.values = riceThresholds(stats, request.false_alarms_per_hour / 3600.0 / n);
  out.source = "calibration " + request.calibration_file;
  out.calibration_rms = stats.rms();
  out.calibration_max = stats.max_abs;
  out.calibration_seconds = pass.last - pass.first;
  if ((out.values.array() <= 0.0).any())
    throw InputError(request.calibration_file +
                     ": the calibration residual is zero on some joint (a log without motion or "
                     "torque?): no threshold can be set from it");
  return out;
}

}  // namespace

MonitorThresholds readMonitorThresholds(const std::string& file) {
  const nlohmann::json document = parseJson(readFile(file), file);
  const JsonReader read(file);
  read.header(document, kMonitorThresholdsDocument.schema_version, kMonitorThresholdsDocument.kind);
  read.onlyKeys(
      document, "",
      {"schema_version", "kind", "robot", "joints", "residual", "gain", "thresholds", "source",
       "false_alarms_per_hour", "calibration_rms", "calibration_max", "calibration_seconds"});
  MonitorThresholds out;
  out.robot = read.string(document, "", "robot");
  out.joint_names = read.strings(read.field(document, "", "joints"), "joints");
  const long n = static_cast<long>(out.joint_names.size());
  const std::string residual = read.string(document, "", "residual");
  if (residual != "observer" && residual != "direct")
    read.fail("residual", "expected observer or direct");
  out.residual = residual == "direct" ? MonitorResidual::kDirect : MonitorResidual::kObserver;
  out.gain = read.vector(read.field(document, "", "gain"), "gain", n);
  out.values = read.vector(read.field(document, "", "thresholds"), "thresholds", n);
  for (Eigen::Index j = 0; j < n; ++j) {
    if (!(out.values[j] > 0.0) || !std::isfinite(out.values[j]))
      read.fail(JsonReader::index("thresholds", j), "expected a positive finite number");
    if (!(out.gain[j] > 0.0) || !std::isfinite(out.gain[j]))
      read.fail(JsonReader::index("gain", j), "expected a positive finite number");
  }
  out.source = "thresholds " + file;
  if (document.contains("false_alarms_per_hour"))
    out.false_alarms_per_hour = read.number(document, "", "false_alarms_per_hour", 0.0, 1e9);
  return out;
}

namespace {

/// The observer gain per joint (one value for all, or the default); InputError for another count.
Eigen::VectorXd checkedGain(const MonitorRequest& request, const Model& model) {
  const int n = model.numJoints();
  Eigen::VectorXd gain = request.gain.value_or(Eigen::VectorXd::Constant(n, kDefaultObserverGain));
  if (gain.size() == 1) gain = Eigen::VectorXd::Constant(n, gain[0]);  // one value for all
  if (gain.size() != n)
    throw InputError("--gain has " + std::to_string(gain.size()) + " values, the robot '" +
                     model.name + "' has " + std::to_string(n) + " joints");
  return gain;
}

/// The torque constants against the logs (they convert raw efforts: a recording's or stdin's)
/// and against the estimate's own (a warning when they are missing or differ).
void checkEffortScale(const MonitorRequest& request, const LoadedArm& arm,
                      std::vector<std::string>& warnings) {
  const Eigen::VectorXd scale = effortScale(request, arm.model.numJoints());
  const bool raw_efforts = rawEfforts(request.data_file) || (!request.calibration_file.empty() &&
                                                             rawEfforts(request.calibration_file));
  if (scale.size() > 0 && !raw_efforts)
    throw InputError(
        "--torque-constants converts the raw efforts of a recording or of samples on stdin; the "
        "dataset CSVs given hold torques already (dynid prepare --current converted them): drop "
        "--torque-constants");
  if (raw_efforts) currentsWarning(arm, request, scale, warnings);
}

}  // namespace

MonitorOutcome monitorRun(const MonitorRequest& request) {
  request.check();
  MonitorOutcome out;
  const LoadedArm arm = loadArm(request.arm, request.robot_spec, std::nullopt, &out.warnings);
  out.model = arm.model;
  out.robot_spec = arm.robot_spec;
  const Model& model = out.model;
  const int n = model.numJoints();
  Eigen::VectorXd gain = checkedGain(request, model);
  checkEffortScale(request, arm, out.warnings);
  // The thresholds: calibrated on a clean log, or read back (for these joints, this gain).
  if (!request.calibration_file.empty()) {
    out.thresholds = calibrate(model, request, gain, out.warnings);
  } else {
    out.thresholds = readMonitorThresholds(request.thresholds_file);
    if (out.thresholds.joint_names != model.joint_names)
      throw InputError(
          request.thresholds_file + ": thresholds for the joints of '" + out.thresholds.robot +
          "' (" + std::to_string(out.thresholds.joint_names.size()) + " joints), not those of '" +
          model.name + "': calibrate again on this robot's log");
    if (request.gain && (gain - out.thresholds.gain).norm() != 0.0)
      throw InputError(request.thresholds_file +
                       ": calibrated with another observer gain; drop --gain or calibrate again");
    if (out.thresholds.residual != request.residual)
      throw InputError(
          request.thresholds_file + ": thresholds of the " +
          (out.thresholds.residual == MonitorResidual::kDirect ? "direct" : "observer") +
          " residual; give the same --residual");
    gain = out.thresholds.gain;
  }
  // The monitored pass.
  const bool direct_events = request.residual == MonitorResidual::kDirect;
  ResidualStatistics observer_stats, direct_stats;
  observer_stats.reset(n);
  direct_stats.reset(n);
  out.observer_envelope.reset(n);
  out.direct_envelope.reset(n);
  EventDetector detector(out.thresholds.values, request.hold, request.sink, out.events);
  const Visit visit = [&](double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd* d,
                          const Eigen::VectorXd& dq) {
    observer_stats.add(t, r, nullptr, 0.0);
    out.observer_envelope.add(t, r);
    if (d) {
      direct_stats.add(t, *d, nullptr, 0.0);
      out.direct_envelope.add(t, *d);
    }
    detector.add(t, dt, direct_events ? *d : r, dq);
  };
  Pass pass;
  if (request.data_file == "-") {
    pass = passOverStream(
        model, request, gain,
        [&](double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd* d,
            const Eigen::VectorXd& dq) {
          if (direct_events && !d)
            throw InputError("--residual direct needs ddq: the stream's header has no ddq columns");
          visit(t, dt, r, d, dq);
        });
  } else {
    pass = passOverLog(
        model, request.data_file, request, gain,
        [&](double t, double dt, const Eigen::VectorXd& r, const Eigen::VectorXd* d,
            const Eigen::VectorXd& dq) {
          if (direct_events && !d) throw InputError(request.data_file + ": " + kDirectNeedsDdq);
          visit(t, dt, r, d, dq);
        },
        out.warnings);
  }
  detector.close();
  out.samples = pass.samples;
  out.seconds = pass.last - pass.first;
  out.restarts = pass.restarts;
  out.has_direct = pass.has_direct;
  out.interrupted = pass.interrupted;
  out.observer_rms = observer_stats.rms();
  out.observer_max = observer_stats.max_abs;
  if (pass.has_direct) {
    out.direct_rms = direct_stats.rms();
    out.direct_max = direct_stats.max_abs;
  }
  if (out.samples == 0) throw InputError(request.data_file + ": no samples to monitor");
  if (pass.restarts > 0)
    out.warnings.push_back(std::to_string(pass.restarts) + " gap(s) longer than " +
                           std::to_string(request.max_gap) +
                           " s: the observer restarted after each (no external torque assumed "
                           "at a restart)");
  if (!request.truth_file.empty())
    out.truth = scoreEvents(truthEpisodes(request.truth_file, n), out.events);
  return out;
}

}  // namespace dynid
