#include "analysis/monitor/feeds.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <deque>
#include <limits>

#include "analysis/logs/bag_log.hpp"
#include "analysis/logs/effort_scale.hpp"
#include "analysis/monitor/observer.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/parallel.hpp"
#include "core/rnea.hpp"
#include "data/bags/bag.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"

namespace dynid {

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

namespace {

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

}  // namespace

Pass passOverStream(const Model& model, const MonitorRequest& request, const Eigen::VectorXd& gain,
                    const Visit& visit) {
  const int n = model.numJoints();
  const std::string source = "<stdin>";
  std::string line;
  if (!request.next_line || !request.next_line(line)) {
    Pass none;  // Ctrl-C while waiting for the header: no sample, not a malformed stream
    none.interrupted = request.control.stopped();
    if (none.interrupted) return none;
    throw ParseError(source, 1, "", "no header: the stream ended before its first line");
  }
  const bool with_ddq = parseSampleHeader(line, n, source);
  const Eigen::VectorXd scale =
      effortScale(request.torque_constants, request.gear_ratios, n, "the robot");
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

const char* const kDirectNeedsDdq =
    "a recording has no ddq, and `residual` direct needs it: use the observer, or prepare the "
    "recording (dynid prepare) and monitor the dataset";

namespace {

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
        scale_(effortScale(request.torque_constants, request.gear_ratios, model.numJoints(),
                           "the robot")) {}
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
         "recording first (dynid prepare `log` " +
         path + " `robot` ROBOT `out` DIR) and monitor DIR/train.csv";
}

/// A recording whose efforts are on another topic: read whole (the efforts interpolated at the
/// positions' stamps) and fed in time order. Returns the messages skipped (repeated stamps).
long long feedWhole(const LogSource& source, const std::string& path, const MonitorRequest& request,
                    int n, RecordingFeed& feed, Pass& out, std::vector<std::string>& warnings) {
  long long skipped = 0;
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
  return skipped;
}

/// A recording streamed in constant memory through a reorder window of kReorderWindow, fed in
/// stamp order. Returns the messages skipped (repeated stamps, or later than the window allows).
long long feedStreamed(const LogSource& source, const std::string& path,
                       const MonitorRequest& request, int n, RecordingFeed& feed, Pass& out,
                       std::vector<std::string>& warnings) {
  long long skipped = 0;
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
    if (const std::string w = prefixWarning(scan); !w.empty()) warnings.push_back(path + ": " + w);
  } catch (const Stopped&) {
    out.interrupted = true;
  }
  return skipped;
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
    throw InputError("the joint names given (`joint_names`) are " +
                     std::to_string(source.joint_names.size()) + ", the arm has " +
                     std::to_string(n) + " joints");
  source.joint_prefix = request.joint_prefix;
  Pass out;
  RecordingFeed feed(model, path, request, gain, visit, out);
  const long long skipped = request.effort_topic.empty()
                                ? feedStreamed(source, path, request, n, feed, out, warnings)
                                : feedWhole(source, path, request, n, feed, out, warnings);
  if (skipped > 0)
    warnings.push_back(path + ": " + std::to_string(skipped) +
                       " message(s) repeated an earlier stamp (or came more than " +
                       formatNumber(kReorderWindow) +
                       " s after later-stamped ones) and were skipped");
  return out;
}

/// One pass over a dataset CSV or a recording (by its name: data/bags/bag.hpp's isBag).

}  // namespace

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
                         " (dynid simulate `disturbance`'s ground truth)");
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

}  // namespace dynid
