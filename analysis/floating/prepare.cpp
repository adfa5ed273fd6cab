#include "analysis/floating/prepare.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"
#include "core/signal.hpp"
#include "data/bags/bag.hpp"
#include "data/bags/ros_messages.hpp"
#include "data/floating/floating_log.hpp"

namespace dynid {

void FloatingPrepareOptions::check() const {
  // The ranges of prepare's own options (core/option_ranges.hpp), named as this request's fields.
  checkOption("prepare", "rate", rate, "`rate`");
  checkOption("prepare", "order", order, "`order`");
  checkOption("prepare", "max-gap", max_gap, "`max_gap`");
  checkOption("prepare", "trim", trim, "`trim`");
  checkOption("prepare", "contact-threshold", contact_threshold, "`contact_threshold`");
  if (!std::isfinite(cutoff) || cutoff > 1e7)
    throw InputError("`cutoff` must be a frequency [Hz] below 1e7, 0 (none) or < 0 (the default)");
}

namespace {

enum class Kind { kJoints, kImu, kWrench, kFlag };

/// One topic's messages as rows of numbers, in the order read.
struct Stream {
  Kind kind = Kind::kJoints;
  FloatingTopicSummary summary;
  std::vector<std::int64_t> stamps;  // a bag's [ns]
  std::vector<double> seconds;       // [s] from the joint topic's first stamp (a table's t)
  std::vector<double> values;        // row-major, `width` per message; an IMU's orientation the
                                     // base's
  int width = 0;
  bool has_dq = false, has_tau = false;  // joints
  Eigen::VectorXd time;                  // [s] from the origin, sorted, without repeats
  Eigen::MatrixXd rows;                  // one message a row
  std::vector<std::pair<double, double>> gaps;
};

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

bool isType(std::string_view type, std::string_view ros2, std::string_view ros1) {
  return type == ros2 || type == ros1;
}

/// The topic of a type to read: the named one (which must be of that type), or the only one.
std::string chooseTopic(const std::map<std::string, std::string>& types, const std::string& name,
                        std::string_view ros2, std::string_view ros1, const std::string& path,
                        const char* field) {
  std::vector<std::string> of_type;
  for (const auto& [topic, type] : types)
    if (isType(type, ros2, ros1)) of_type.push_back(topic);
  if (!name.empty()) {
    const auto it = types.find(name);
    if (it == types.end())
      throw InputError(path + ": no topic '" + name + "' (`" + field + "`); its " +
                       std::string(ros2) +
                       " topics: " + (of_type.empty() ? "none" : listed(of_type)));
    if (!isType(it->second, ros2, ros1))
      throw InputError(path + ": topic '" + name + "' (`" + field + "`) holds " + it->second +
                       ", not " + std::string(ros2));
    return name;
  }
  if (of_type.empty())
    throw InputError(path + ": no " + std::string(ros2) +
                     " topic; its topics: " + (types.empty() ? "none" : [&] {
                       std::vector<std::string> all;
                       for (const auto& [topic, type] : types)
                         all.push_back(topic + " (" + type + ")");
                       return listed(all);
                     }()));
  if (of_type.size() > 1)
    throw InputError(path + ": " + std::to_string(of_type.size()) + " " + std::string(ros2) +
                     " topics (" + listed(of_type) + "): name one in `" + field + "`");
  return of_type.front();
}

/// The topics read, each a Stream, joints first, then the IMU, then the wrenches.
std::vector<Stream> chooseStreams(const std::string& path, const FloatingLogTopics& topics) {
  std::map<std::string, std::string> types;
  bags::readBag(path, {}, [&](const bags::BagMessage& m) {
    types.emplace(std::string(m.topic), std::string(m.type));
  });
  std::vector<Stream> out(2);
  out[0].kind = Kind::kJoints;
  out[0].summary.topic = chooseTopic(types, topics.joint_topic, bags::kJointStateRos2,
                                     bags::kJointStateRos1, path, "joint_topic");
  out[1].kind = Kind::kImu;
  out[1].summary.topic =
      chooseTopic(types, topics.imu_topic, bags::kImuRos2, bags::kImuRos1, path, "imu_topic");
  std::vector<std::string> wrenches = topics.wrench_topics;
  if (wrenches.empty())
    for (const auto& [topic, type] : types)
      if (isType(type, bags::kWrenchStampedRos2, bags::kWrenchStampedRos1))
        wrenches.push_back(topic);
  for (const std::string& w : wrenches) {
    Stream s;
    s.kind = Kind::kWrench;
    s.summary.topic = chooseTopic(types, w, bags::kWrenchStampedRos2, bags::kWrenchStampedRos1,
                                  path, "wrench_topics");
    out.push_back(std::move(s));
  }
  for (const auto& [topic, frame] : topics.contact_topics) {
    Stream s;
    s.kind = Kind::kFlag;
    s.summary.topic =
        chooseTopic(types, topic, bags::kBoolRos2, bags::kBoolRos1, path, "contact_topics");
    s.summary.frame = frame;
    out.push_back(std::move(s));
  }
  for (Stream& s : out) s.summary.type = types.at(s.summary.topic);
  return out;
}

/// The model's frames, listed for a message that names an unknown one.
std::string frameList(const FloatingModel& model) {
  std::vector<std::string> names;
  for (const BodyFrame& b : model.frames) names.push_back(b.name);
  return listed(names);
}

/// A contact topic's frame: a frame of the model (its frames listed otherwise).
void checkContactFrame(const FloatingModel& model, const Stream& s, const std::string& path) {
  if (model.findFrame(s.summary.frame) != nullptr) return;
  throw InputError(path + ", topic " + s.summary.topic + " (`contact_topics`): '" +
                   s.summary.frame + "' is no frame of '" + model.name() +
                   "'; its frames: " + frameList(model));
}

/// The joint message's values in the model's joint order: q, then dq and tau when the first
/// message carries them (every later one must too).
void addJoints(const FloatingModel& model, const bags::JointStateMessage& m, Stream& s,
               std::vector<int>& index, const std::string& where) {
  const int n = model.numJoints();
  if (s.stamps.empty()) {
    std::vector<std::string> missing;
    for (int j = 0; j < n; ++j) {
      const std::string& name = model.limbs().joint_names[static_cast<std::size_t>(j)];
      const auto it = std::find(m.name.begin(), m.name.end(), name);
      if (it == m.name.end()) missing.push_back(name);
      index.push_back(static_cast<int>(it - m.name.begin()));
    }
    if (!missing.empty())
      throw InputError(where + ": the messages lack joints of '" + model.name() +
                       "': " + listed(missing) + "; they name " + listed(m.name));
    s.has_dq = m.velocity.size() == m.name.size();
    s.has_tau = m.effort.size() == m.name.size();
    s.width = n * (1 + (s.has_dq ? 1 : 0) + (s.has_tau ? 1 : 0));
  }
  if (m.position.size() != m.name.size() || (s.has_dq && m.velocity.size() != m.name.size()) ||
      (s.has_tau && m.effort.size() != m.name.size()))
    throw InputError(where + ", message " + std::to_string(s.stamps.size() + 1) +
                     ": position, velocity or effort not one per name as in the first message");
  for (const std::vector<double>* v : {&m.position, &m.velocity, &m.effort}) {
    if ((v == &m.velocity && !s.has_dq) || (v == &m.effort && !s.has_tau)) continue;
    for (int j = 0; j < n; ++j) s.values.push_back((*v)[static_cast<std::size_t>(index[j])]);
  }
}

/// The header frame of an Imu or WrenchStamped topic: the same in every message, a frame of the
/// model (an IMU's on the base body).
void checkFrame(const FloatingModel& model, const std::string& frame, Stream& s,
                const std::string& where) {
  if (!s.stamps.empty()) {
    if (frame != s.summary.frame)
      throw InputError(where + ", message " + std::to_string(s.stamps.size() + 1) + ": frame_id '" +
                       frame + "' after '" + s.summary.frame + "' (one frame per topic)");
    return;
  }
  s.summary.frame = frame;
  const BodyFrame* f = model.findFrame(frame);
  if (f == nullptr)
    throw InputError(where + ": frame_id '" + frame + "' is no frame of '" + model.name() + "' (" +
                     (s.kind == Kind::kImu ? "an IMU" : "a wrench") +
                     " in an unknown frame); its frames: " + frameList(model));
  if (s.kind == Kind::kImu && f->body != -1)
    throw InputError(where + ": the IMU's frame '" + frame +
                     "' is on a limb: only an IMU on the base body ('" + model.baseName() +
                     "') gives the base's motion");
}

/// Pass 2: every chosen topic's messages decoded into its stream.
void readStreams(const FloatingModel& model, const std::string& path, bool receive_time,
                 std::vector<Stream>& streams) {
  std::map<std::string, Stream*> by_topic;
  std::vector<std::string> names;
  for (Stream& s : streams) {
    if (s.kind == Kind::kFlag) checkContactFrame(model, s, path);
    by_topic[s.summary.topic] = &s;
    names.push_back(s.summary.topic);
  }
  std::vector<int> joint_index;
  bags::JointStateMessage js;
  bags::ImuMessage imu;
  bags::WrenchStampedMessage wrench;
  bags::readBag(path, names, [&](const bags::BagMessage& m) {
    Stream& s = *by_topic.at(std::string(m.topic));
    const bool cdr = m.encoding == bags::Encoding::kCdr;
    const std::string& file = m.file ? *m.file : path;
    const std::string where = path + ", topic " + s.summary.topic;
    std::int64_t stamp = 0;
    if (s.kind == Kind::kJoints) {
      cdr ? bags::decodeJointStateCdr(m.data, file, m.offset, js)
          : bags::decodeJointStateRos1(m.data, file, m.offset, js);
      addJoints(model, js, s, joint_index, where);
      stamp = js.stamp_ns;
    } else if (s.kind == Kind::kImu) {
      cdr ? bags::decodeImuCdr(m.data, file, m.offset, imu)
          : bags::decodeImuRos1(m.data, file, m.offset, imu);
      checkFrame(model, imu.frame_id, s, where);
      if (!imu.hasOrientation())
        throw InputError(where +
                         ": the IMU gives no orientation (orientation_covariance[0] = "
                         "-1): gravity's direction in the base frame needs it");
      // The IMU's orientation, then the base's: world <- IMU times (base <- IMU)^T.
      const auto& o = imu.orientation;
      const Eigen::Vector4d wxyz(o[3], o[0], o[1], o[2]);
      if (!(std::abs(wxyz.norm() - 1.0) <= kQuaternionNormTolerance))
        throw InputError(where + ", message " + std::to_string(s.stamps.size() + 1) +
                         ": the orientation's norm is " + formatNumber(wxyz.norm(), 6) +
                         ", not a unit quaternion");
      const Eigen::Quaterniond base_q =
          Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).normalized() *
          Eigen::Quaterniond(model.findFrame(imu.frame_id)->placement.rotation).conjugate();
      s.values.insert(s.values.end(), {base_q.w(), base_q.x(), base_q.y(), base_q.z()});
      s.values.insert(s.values.end(), imu.angular_velocity.begin(), imu.angular_velocity.end());
      s.values.insert(s.values.end(), imu.linear_acceleration.begin(),
                      imu.linear_acceleration.end());
      s.width = 10;
      stamp = imu.stamp_ns;
    } else if (s.kind == Kind::kFlag) {
      const bool holds = cdr ? bags::decodeBoolCdr(m.data, file, m.offset)
                             : bags::decodeBoolRos1(m.data, file, m.offset);
      s.values.push_back(holds ? 1.0 : 0.0);
      s.width = 1;
      s.stamps.push_back(m.receive_ns);  // no header
      return;
    } else {
      cdr ? bags::decodeWrenchStampedCdr(m.data, file, m.offset, wrench)
          : bags::decodeWrenchStampedRos1(m.data, file, m.offset, wrench);
      checkFrame(model, wrench.frame_id, s, where);
      s.values.insert(s.values.end(), wrench.torque.begin(), wrench.torque.end());
      s.values.insert(s.values.end(), wrench.force.begin(), wrench.force.end());
      s.width = 6;
      stamp = wrench.stamp_ns;
    }
    s.stamps.push_back(receive_time ? m.receive_ns : stamp);
  });
  for (Stream& s : streams) {
    s.summary.messages = static_cast<long long>(s.stamps.size());
    if (s.stamps.size() < 2)
      throw InputError(path + ", topic " + s.summary.topic + ": " +
                       std::to_string(s.stamps.size()) + " message(s); a signal needs two or more");
    if (std::all_of(s.stamps.begin(), s.stamps.end(), [](std::int64_t t) { return t == 0; }))
      throw InputError(path + ", topic " + s.summary.topic +
                       ": every header stamp is zero; stamp by the receive time instead "
                       "(`receive_time`)");
  }
}

/// Sorted by time (stable), repeated times dropped (the first kept); an IMU's quaternions each on
/// the previous one's side (q and -q are one rotation: interpolating between them would pass
/// through zero); the median step, the gap limit and the gaps.
void orderStream(Stream& s, double max_gap) {
  std::vector<std::size_t> order(s.seconds.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return s.seconds[a] < s.seconds[b]; });
  std::vector<std::size_t> kept;
  for (std::size_t i : order)
    if (kept.empty() || s.seconds[i] != s.seconds[kept.back()]) kept.push_back(i);
  s.summary.repeated = static_cast<long long>(order.size() - kept.size());
  const auto N = static_cast<Eigen::Index>(kept.size());
  if (N < 2)
    throw InputError(s.summary.topic + ": " + std::to_string(N) +
                     " sample(s) at distinct times; a signal needs two or more");
  s.time.resize(N);
  s.rows.resize(N, s.width);
  for (Eigen::Index k = 0; k < N; ++k) {
    const std::size_t i = kept[static_cast<std::size_t>(k)];
    s.time[k] = s.seconds[i];
    for (int c = 0; c < s.width; ++c)
      s.rows(k, c) = s.values[i * static_cast<std::size_t>(s.width) + static_cast<std::size_t>(c)];
  }
  if (s.kind == Kind::kImu)
    for (Eigen::Index k = 1; k < N; ++k)
      if (s.rows.row(k).head<4>().dot(s.rows.row(k - 1).head<4>()) < 0.0)
        s.rows.row(k).head<4>() *= -1.0;
  std::vector<double> steps(static_cast<std::size_t>(N - 1));
  for (Eigen::Index k = 1; k < N; ++k)
    steps[static_cast<std::size_t>(k - 1)] = s.time[k] - s.time[k - 1];
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  s.summary.median_step = steps[steps.size() / 2];
  s.summary.gap_limit = max_gap > 0.0 ? max_gap : 5.0 * s.summary.median_step;
  // A flag holds from each message to the next (a contact switch may publish only when it
  // changes): its silences are no gaps.
  for (Eigen::Index k = 1; k < N && s.kind != Kind::kFlag; ++k)
    if (s.time[k] - s.time[k - 1] > s.summary.gap_limit)
      s.gaps.emplace_back(s.time[k - 1], s.time[k]);
  s.summary.gaps = static_cast<int>(s.gaps.size());
  s.stamps = {};
  s.seconds = {};
  s.values = {};
}

/// The rate, the cutoff and the trim, and why.
void chooseRates(const Stream& joints, const FloatingPrepareOptions& options,
                 FloatingPrepareOutcome& out) {
  if (options.rate > 0.0) {
    out.rate = options.rate;
    out.rate_reason = "as asked";
  } else {
    out.rate = 1.0 / joints.summary.median_step;
    out.rate_reason = "the joint topic's median step's";
  }
  if (options.cutoff < 0.0) {
    out.cutoff = out.rate >= 40.0 ? 10.0 : out.rate / 4.0;
    out.cutoff_reason = out.rate >= 40.0 ? "the default, 10 Hz" : "a quarter of the rate";
  } else {
    out.cutoff = options.cutoff;
    out.cutoff_reason = options.cutoff == 0.0 ? "no filter, as asked" : "as asked";
  }
  if (out.cutoff >= out.rate / 2.0)
    throw InputError("`cutoff` " + formatNumber(out.cutoff, 6) +
                     " Hz is not below half the rate (" + formatNumber(out.rate / 2.0, 6) + " Hz)");
  out.trim = options.trim >= 0.0 ? options.trim : out.cutoff > 0.0 ? 2.0 / out.cutoff : 0.0;
}

/// A run of the uniform grid: its first sample's index and its length.
struct Run {
  Eigen::Index first = 0, count = 0;
};

/// The grid's runs: every topic within its gap limit, over the span all topics cover.
std::vector<Run> findRuns(const std::vector<Stream>& streams, const std::string& path,
                          FloatingPrepareOutcome& out) {
  out.span_from = -INFINITY;
  out.span_to = INFINITY;
  std::string spans;
  for (const Stream& s : streams) {
    out.span_from = std::max(out.span_from, s.time[0]);
    // A flag's last message holds to the end of the other signals.
    if (s.kind != Kind::kFlag) out.span_to = std::min(out.span_to, s.time[s.time.size() - 1]);
    spans += (spans.empty() ? "" : ", ") + s.summary.topic + " " + formatNumber(s.time[0], 6) +
             " to " + formatNumber(s.time[s.time.size() - 1], 6) + " s";
  }
  if (!(out.span_to > out.span_from))
    throw InputError(path + ": the topics never all cover one time (" + spans + ")");
  const double samples = std::floor((out.span_to - out.span_from) * out.rate + 1e-9) + 1.0;
  if (samples > 5e7)
    throw InputError(path + ": " + formatNumber(samples, 6) + " samples at " +
                     formatNumber(out.rate, 6) + " Hz: more than 5e7; lower `rate`");
  const auto count = static_cast<Eigen::Index>(samples);
  std::vector<char> valid(static_cast<std::size_t>(count), 1);
  for (const Stream& s : streams)
    for (const auto& [a, b] : s.gaps) {  // grid times strictly inside the gap
      const auto from = static_cast<Eigen::Index>(std::floor((a - out.span_from) * out.rate)) + 1;
      const auto to = static_cast<Eigen::Index>(std::ceil((b - out.span_from) * out.rate)) - 1;
      for (Eigen::Index k = std::max<Eigen::Index>(from, 0); k <= std::min(to, count - 1); ++k)
        valid[static_cast<std::size_t>(k)] = 0;
    }
  const auto trim = static_cast<Eigen::Index>(std::llround(out.trim * out.rate));
  std::vector<Run> runs;
  for (Eigen::Index k = 0; k < count;) {
    if (!valid[static_cast<std::size_t>(k)]) {
      ++k;
      continue;
    }
    Run r{k, 0};
    while (k < count && valid[static_cast<std::size_t>(k)]) ++k, ++r.count;
    if (r.count - 2 * trim >= 3)
      runs.push_back(r);
    else
      ++out.runs_dropped;
  }
  out.runs = static_cast<int>(runs.size());
  if (runs.empty())
    throw InputError(path + ": no run of " + formatNumber(2.0 * out.trim + 3.0 / out.rate, 6) +
                     " s or more between gaps (the filter's trim of " + formatNumber(out.trim, 6) +
                     " s at each end, and three samples)");
  return runs;
}

/// A stream over a run: resampled, low-passed (when a cutoff is set); a flag held from its last
/// sample at or before each time (never interpolated or filtered).
Eigen::MatrixXd runSignals(const Stream& s, double t0, const FloatingPrepareOutcome& out,
                           Eigen::Index count, const std::vector<Biquad>& filter) {
  if (s.kind == Kind::kFlag) {
    Eigen::MatrixXd x(count, 1);
    for (Eigen::Index k = 0; k < count; ++k) {
      const double t = t0 + static_cast<double>(k) / out.rate;
      const auto after = std::upper_bound(s.time.data(), s.time.data() + s.time.size(), t + 1e-9);
      x(k, 0) = s.rows(std::max<Eigen::Index>(after - s.time.data() - 1, 0), 0);
    }
    return x;
  }
  Eigen::MatrixXd x = resampleLinear(s.time, s.rows, t0, out.rate, static_cast<int>(count));
  if (!filter.empty())
    for (Eigen::Index c = 0; c < x.cols(); ++c) {
      Eigen::VectorXd column = x.col(c);
      filtfiltInPlace(filter, column);
      x.col(c) = column;
    }
  return x;
}

/// A run's samples into the dataset from `at` on (the trimmed part).
void appendRun(const FloatingModel& model, const std::vector<Stream>& streams, const Run& run,
               const FloatingPrepareOutcome& out, const std::vector<Biquad>& filter,
               Eigen::Index& at, FloatingDataset& d) {
  const double t0 = out.span_from + static_cast<double>(run.first) / out.rate, h = 1.0 / out.rate;
  const int n = model.numJoints();
  const Eigen::MatrixXd joints = runSignals(streams[0], t0, out, run.count, filter);
  const Eigen::MatrixXd imu = runSignals(streams[1], t0, out, run.count, filter);
  std::vector<Eigen::MatrixXd> wrenches, flags;
  for (std::size_t k = 2; k < streams.size(); ++k)
    (streams[k].kind == Kind::kFlag ? flags : wrenches)
        .push_back(runSignals(streams[k], t0, out, run.count, filter));
  Eigen::MatrixXd dq(run.count, n), ddq(run.count, n), dgyro(run.count, 3);
  for (int j = 0; j < n; ++j) {
    dq.col(j) =
        streams[0].has_dq ? Eigen::VectorXd(joints.col(n + j)) : derivative(joints.col(j), h);
    ddq.col(j) = derivative(dq.col(j), h);
  }
  for (int c = 0; c < 3; ++c) dgyro.col(c) = derivative(imu.col(4 + c), h);
  const Pose<double>& F = model.findFrame(streams[1].summary.frame)->placement;
  const auto trim = static_cast<Eigen::Index>(std::llround(out.trim * out.rate));
  const int tau_at = streams[0].has_dq ? 2 * n : n;
  for (Eigen::Index k = trim; k < run.count - trim; ++k, ++at) {
    d.time[at] = t0 + static_cast<double>(k) * h;
    const Eigen::Vector4d base_q = imu.row(k).head<4>().transpose().normalized();
    d.orientation.col(at) = base_q;
    imuBaseMotion(model, F, baseRotation(base_q), imu.row(k).segment<3>(4).transpose(),
                  dgyro.row(k).transpose(), imu.row(k).segment<3>(7).transpose(), d.twist.col(at),
                  d.acceleration.col(at));
    d.q.col(at) = joints.row(k).head(n).transpose();
    d.dq.col(at) = dq.row(k).transpose();
    d.ddq.col(at) = ddq.row(k).transpose();
    if (d.hasTorques()) d.tau.col(at) = joints.row(k).segment(tau_at, n).transpose();
    for (std::size_t w = 0; w < wrenches.size(); ++w)
      d.wrenches[w].values.col(at) = wrenches[w].row(k).transpose();
    for (std::size_t f = 0; f < flags.size(); ++f)
      d.flags[f].holding[static_cast<std::size_t>(at)] = flags[f](k, 0) != 0.0 ? 1 : 0;
  }
}

/// A signal sampled slower than twice the band the output keeps (the cutoff; without a filter,
/// half the output rate) is mostly its linear interpolation there: its derivatives (the base's
/// angular acceleration from a slow IMU) step at its own samples. Said, with the rates.
void slowSignalWarnings(const std::vector<Stream>& streams, FloatingPrepareOutcome& out) {
  const double band = out.cutoff > 0.0 ? out.cutoff : out.rate / 2.0;
  for (const Stream& s : streams) {
    const double rate = 1.0 / s.summary.median_step;
    if (s.kind == Kind::kFlag || !(rate < 2.0 * band)) continue;
    out.warnings.push_back(
        s.summary.topic + " is sampled at " + formatNumber(rate, 4) + " Hz, below twice the " +
        formatNumber(band, 4) + " Hz the dataset keeps (" +
        (out.cutoff > 0.0 ? "the low-pass" : "half its rate") +
        "): between its samples the dataset holds their straight line, and its derivatives " +
        (s.kind == Kind::kImu ? "(the base's angular acceleration) " : "") +
        "step at them; a `cutoff` below half its rate keeps only what it measured");
  }
}

/// Contact flags from the prepared wrenches: a frame holds where its force's norm reaches the
/// threshold; a frame with a flag of its own keeps it (said).
void thresholdFlags(const std::string& path, double threshold, FloatingPrepareOutcome& out) {
  if (threshold <= 0.0) return;
  FloatingDataset& d = out.dataset;
  if (d.wrenches.empty())
    throw InputError(path + ": `contact_threshold` sets contact flags from wrenches, and the log " +
                     "has none");
  const int N = d.numSamples();
  for (const FloatingDataset::Wrench& w : d.wrenches) {
    if (d.findFlag(w.frame) != nullptr) {
      out.warnings.push_back("`contact_threshold` leaves the contact flag of " + w.frame +
                             " as the log records it");
      continue;
    }
    FloatingDataset::Flag flag{w.frame, std::vector<char>(static_cast<std::size_t>(N), 0)};
    int held = 0;
    for (int k = 0; k < N; ++k) {
      const bool holds = w.values.col(k).tail<3>().norm() >= threshold;
      flag.holding[static_cast<std::size_t>(k)] = holds ? 1 : 0;
      held += holds ? 1 : 0;
    }
    out.thresholded.emplace_back(w.frame, N > 0 ? static_cast<double>(held) / N : 0.0);
    d.flags.push_back(std::move(flag));
  }
}

/// The streams (joints, the IMU, the wrenches, then the flags; times in seconds) into the
/// dataset: ordered, on one time base over the runs, filtered and differentiated.
FloatingPrepareOutcome prepareStreams(const FloatingModel& model, const std::string& path,
                                      std::vector<Stream>& streams,
                                      const FloatingPrepareOptions& options) {
  FloatingPrepareOutcome out;
  for (std::size_t a = 2; a < streams.size(); ++a)
    for (std::size_t b = 2; b < a; ++b)
      if (streams[a].kind == streams[b].kind &&
          streams[a].summary.frame == streams[b].summary.frame)
        throw InputError(path + ": " + streams[b].summary.topic + " and " +
                         streams[a].summary.topic + " both measure frame '" +
                         streams[a].summary.frame + "'");
  for (Stream& s : streams) orderStream(s, options.max_gap);
  chooseRates(streams[0], options, out);
  const std::vector<Run> runs = findRuns(streams, path, out);
  const std::vector<Biquad> filter = out.cutoff > 0.0
                                         ? butterworthLowPass(options.order, out.cutoff, out.rate)
                                         : std::vector<Biquad>{};
  const auto trim = static_cast<Eigen::Index>(std::llround(out.trim * out.rate));
  Eigen::Index total = 0;
  for (const Run& r : runs) total += r.count - 2 * trim;
  FloatingDataset& d = out.dataset;
  d.file = path;
  d.joints = model.limbs().joint_names;
  const int n = model.numJoints();
  d.time.resize(total);
  d.orientation.resize(4, total);
  d.twist.resize(6, total);
  d.acceleration.resize(6, total);
  d.q.resize(n, total);
  d.dq.resize(n, total);
  d.ddq.resize(n, total);
  d.tau.resize(streams[0].has_tau ? n : 0, total);
  for (std::size_t k = 2; k < streams.size(); ++k) {
    if (streams[k].kind == Kind::kFlag)
      d.flags.push_back({streams[k].summary.frame, std::vector<char>(total, 0)});
    else
      d.wrenches.push_back({streams[k].summary.frame, Eigen::MatrixXd(streams[k].width, total)});
  }
  Eigen::Index at = 0;
  for (const Run& r : runs) appendRun(model, streams, r, out, filter, at, d);
  out.contact_threshold = options.contact_threshold;
  thresholdFlags(path, options.contact_threshold, out);
  for (const Stream& s : streams) out.topics.push_back(s.summary);
  if (!streams[0].has_tau)
    out.warnings.push_back("the log has no joint torques: a dataset for the wrenches set only");
  if (out.runs_dropped > 0)
    out.warnings.push_back(std::to_string(out.runs_dropped) +
                           " run(s) between gaps too short for the filter's trim were dropped");
  slowSignalWarnings(streams, out);
  return out;
}

/// A table's sensors as streams, named by their columns.
std::vector<Stream> tableStreams(const FloatingLogTable& table) {
  std::vector<Stream> out;
  const auto add = [&](const FloatingLogSignal& signal, Kind kind, const std::string& name) {
    Stream s;
    s.kind = kind;
    s.summary.topic = name;
    s.summary.type = "table columns";
    s.summary.frame = signal.frame;
    s.summary.messages = signal.samples();
    s.width = signal.width;
    s.seconds = signal.time;
    s.values = signal.values;
    out.push_back(std::move(s));
  };
  add(table.joints, Kind::kJoints, "q:*");
  out.back().has_dq = table.has_dq;
  out.back().has_tau = table.has_tau;
  add(table.imu, Kind::kImu, "imu:" + table.imu.frame + ":*");
  for (const FloatingLogSignal& w : table.wrenches)
    add(w, Kind::kWrench, "wrench:" + w.frame + ":*");
  for (const FloatingLogSignal& f : table.flags) add(f, Kind::kFlag, "contact:" + f.frame);
  return out;
}

}  // namespace

FloatingPrepareOutcome prepareFloatingLog(const FloatingModel& model, const std::string& path,
                                          const FloatingLogTopics& topics,
                                          const FloatingPrepareOptions& options) {
  options.check();
  if (!bags::isBag(path)) {
    if (!topics.joint_topic.empty() || !topics.imu_topic.empty() || !topics.wrench_topics.empty() ||
        !topics.contact_topics.empty() || options.receive_time)
      throw InputError(
          "`joint_topic`, `imu_topic`, `wrench_topics`, `contact_topics` and `receive_time` apply "
          "to "
          "recordings, not to a table (" +
          path + ")");
    std::vector<Stream> streams = tableStreams(readFloatingLogTable(path, model));
    return prepareStreams(model, path, streams, options);
  }
  std::vector<Stream> streams = chooseStreams(path, topics);
  readStreams(model, path, options.receive_time, streams);
  const std::int64_t origin = *std::min_element(streams[0].stamps.begin(), streams[0].stamps.end());
  for (Stream& s : streams)
    for (std::int64_t stamp : s.stamps)
      s.seconds.push_back(static_cast<double>(stamp - origin) * 1e-9);
  return prepareStreams(model, path, streams, options);
}

}  // namespace dynid
