// dynid monitor: its speed, and its acceptance in simulation (docs/MONITOR.md, "Measured").
//   - BM_ObserverSample/<robot>: one sample of the momentum observer (p = M dq, beta, the update).
//   - BM_MonitorFile/csv: monitorRun on a 60 s, 1 kHz Panda log file (CSV parsing included) with
//     the thresholds its calibration wrote (arm states, moving regimes), read back; its
//     counter hour_seconds is the time an hour of such a log takes. /db3: the same samples as a
//     rosbag2 SQLite recording (JointState decoding included).
//   - BM_MonitorAcceptance/<robot>: the truth is the robot with friction (Fv per rad/s and Fc
//     each 1 % of the joint's peak torque in the motion) and its
//     inertial parameters perturbed by up to 20 % (seeded); the logs are its default sinusoid
//     (tracked at a 2 Hz bandwidth) at 1 kHz with white noise of 0.1 N m on tau and 1e-3 rad/s on
//     dq (q: 1e-5 rad). The identified model is OLS (with the robot's drive terms) on a 60 s
//     training log; the prior is the nominal model without friction (what a URDF gives). Thresholds
//     from one clean 60 s calibration log at 0.1 false alarms per hour. Reported: collisions of 10
//     N m on a random joint (either sign, 0.1 s; 10 per 60 s log, 100 in all) detected within 50
//     ms; false alarms over 60 clean 60 s logs (one hour); the thresholds of the prior over those
//     of the identified model, per joint.
//   - BM_MonitorRegimes/<robot>: the moving regimes (docs/MONITOR.md, "The moving regimes"): the
//     truth, logs and calibration of BM_MonitorStates; pushes in motion of 0.5, 0.75 and 1 times
//     each joint's single moving threshold (0.1 s, 8 per 56 s log, ten logs) and an hour of clean
//     motion with stops, judged by the thresholds with their regimes and by the same without
//     (version 2). /puma560_published: the truth with the PUMA's published drive model (Coulomb
//     friction up to 25 N m through the gears) and a Stribeck term half of it, which the model does
//     not carry.
//   - BM_MonitorStates/<robot>: the arm states (docs/MONITOR.md, "The arm states"). The truth as
//     above plus a Stribeck term half Fc that no identified model carries, tracked at 20 Hz with
//     stops (simulate --pauses). Calibrated on a 120 s log of another motion (4 s moves, 3 s
//     holds); watched: ten 56 s logs (3 s moves, 4 s holds), each with 8 pushes at rest (5 sigma of
//     the torque noise, 0.5 N m, for 0.2 s, in the holds) and 8 in motion (10 N m for 0.1 s),
//     random joint and sign; and an hour of clean motion with stops. The same with the previous
//     release's thresholds (one per joint, none at rest: a version 1 file) beside it.
//     /<robot>_stiction: the truth simulated with stick-slip friction (SimulationOptions::
//     stiction), each push at rest simulated away too, to count those the static friction held
//     (nothing recorded changed).
// Run: build/bench/bench_monitor  (several minutes on 2 cores; counters and a table on stdout).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include "analysis/monitor/monitor.hpp"
#include "analysis/runs/simulate.hpp"
#include "core/format.hpp"
#include "core/momentum.hpp"
#include "core/perturb.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "reports/monitor_report.hpp"
#include "tests/common/joint_state_db3.hpp"
#include "tests/common/monitor_logs.hpp"

namespace dynid {
namespace {

std::string benchDir() {
  const std::string dir = std::filesystem::temp_directory_path() / "dynid_bench_monitor";
  std::filesystem::create_directories(dir);
  return dir;
}

SimulateRequest motion(const Model& truth, double seconds, std::uint64_t seed, double phase) {
  SimulateRequest r;
  r.robot = truth;
  r.amplitude = Eigen::VectorXd::Constant(truth.numJoints(), 0.5);
  r.phase = Eigen::VectorXd::Constant(truth.numJoints(), phase);
  r.simulation.duration = seconds;
  r.simulation.noise_tau = 0.1;
  r.simulation.noise_dq = 1e-3;
  r.simulation.noise_q = 1e-5;
  r.simulation.seed = seed;
  // A 2 Hz tracking bandwidth: at the default 5 Hz, the Panda's diagonal PD gains make its
  // 1 kHz loop unstable (joints 1 and 3 chatter between the torque limits).
  r.bandwidth = 2.0;
  return r;
}

std::string logFile(const SimulateRequest& request, const std::string& name) {
  const std::string path = benchDir() + "/" + name + ".csv";
  writeDatasetCsv(path, simulateRun(request).trajectory);
  return path;
}

void BM_ObserverSample(benchmark::State& state, const Model& model) {
  const int n = model.numJoints();
  MomentumObserver observer(model, Eigen::VectorXd::Constant(n, 100.0));
  std::mt19937_64 rng(1);
  std::normal_distribution<double> normal;
  Eigen::VectorXd q(n), dq(n), tau(n);
  for (int j = 0; j < n; ++j) q[j] = normal(rng), dq[j] = normal(rng), tau[j] = normal(rng);
  double t = 0.0;
  for (auto _ : state) {
    t += 1e-3;
    benchmark::DoNotOptimize(observer.update(t, q, dq, tau).data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(BM_ObserverSample, puma560, makePuma560(true));
BENCHMARK_CAPTURE(BM_ObserverSample, panda, makePanda(true));

/// The log as a rosbag2 recording (JointState with velocities, epoch header stamps).
std::string recordingOf(const std::string& csv, const Model& model) {
  const Trajectory tr = readDatasetCsv(csv);
  const std::string path = csv.substr(0, csv.size() - 4) + ".db3";
  test::JointStateDb3 db3(path);
  for (int k = 0; k < tr.numSamples(); ++k) {
    const Eigen::VectorXd q = tr.q.col(k), dq = tr.dq.col(k), tau = tr.tau.col(k);
    const std::int64_t ns = 1700000000000000000LL + std::llround(tr.time[k] * 1e9);
    db3.add(ns, ns + 200000, model.joint_names, q.data(), dq.data(), tau.data());
  }
  db3.close();
  return path;
}

void BM_MonitorFile(benchmark::State& state, bool recording) {
  const Model panda = makePanda(true);
  const std::string csv = logFile(motion(panda, 60.0, 1, 0.0), "speed");
  const std::string data = recording ? recordingOf(csv, panda) : csv;
  MonitorRequest request;
  request.arm = "panda";
  request.data_file = data;
  request.calibration_file = csv;
  MonitorOutcome first = monitorRun(request);  // the thresholds, once
  // The thresholds document monitor writes (reports/), with its arm states and moving regimes,
  // read back through --thresholds.
  const std::string thresholds = benchDir() + "/speed_thresholds.json";
  writeFileAtomically(thresholds, monitorThresholdsJson(first.thresholds).dump());
  request.calibration_file.clear();
  request.thresholds_file = thresholds;
  long long samples = 0;
  for (auto _ : state) samples += monitorRun(request).samples;
  state.SetItemsProcessed(samples);
  // Seconds per hour of log: the elapsed time over the hours processed.
  state.counters["hour_seconds"] =
      benchmark::Counter(static_cast<double>(samples) / 3.6e6,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK_CAPTURE(BM_MonitorFile, csv, false)->Unit(benchmark::kSecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_MonitorFile, db3, true)->Unit(benchmark::kSecond)->Iterations(3);

/// OLS (the nominal model's drive terms) on a training log; the rest from the nominal model.
Model identified(const Model& nominal, const std::string& training) {
  const Trajectory log = readDatasetCsv(training, nominal.numJoints());
  const BaseParameters base = structuralBaseParameters(nominal);
  LeastSquaresStream stream(base, nominal);
  stream.addTrajectory(nominal, log);
  Model out = nominal;
  out.setStandardParameters(base.standardFromBase(
      stream.estimate(LeastSquaresMethod::kOrdinary).beta, nominal.standardParameters()));
  return out;
}

void BM_MonitorAcceptance(benchmark::State& state, const Model& nominal_drives,
                          const std::string& prior_spec) {
  for (auto _ : state) {
    const int n = nominal_drives.numJoints();
    Model truth = perturbedModel(nominal_drives, 0.2, 5);
    Eigen::VectorXd theta = truth.standardParameters();
    const ParameterLayout layout = truth.parameterLayout();
    // Friction at each joint's scale: Fv (per rad/s) and Fc each 1 % of the joint's peak torque
    // in this motion without friction.
    Model rigid = truth;
    rigid.setDriveTerms(DriveTerms::none());
    const Trajectory reference = simulateRun(motion(rigid, 10.0, 1, 0.0)).trajectory;
    for (int j = 0; j < n; ++j) {
      const double scale = 0.01 * reference.tau.row(j).cwiseAbs().maxCoeff();
      theta[layout.driveIndex(j, DriveTerm::kViscous)] = scale;  // per rad/s
      theta[layout.driveIndex(j, DriveTerm::kCoulomb)] = scale;
      if (layout.drives.has(DriveTerm::kCoulombAsymmetry))  // the PUMA's: symmetric here
        theta[layout.driveIndex(j, DriveTerm::kCoulombAsymmetry)] = 0.0;
    }
    truth.setStandardParameters(theta);
    const std::string tag = truth.name;
    const std::string arm = benchDir() + "/" + tag + "_identified.json";
    writeFileAtomically(
        arm, modelToJson(identified(nominal_drives,
                                    logFile(motion(truth, 60.0, 11, 0.3), tag + "_train"))));
    const std::string calibration = logFile(motion(truth, 60.0, 12, 0.0), tag + "_calibration");
    // Collisions: 10 per 60 s log, 3 s apart from 5 s, random joint and sign, 10 N m for 0.1 s.
    std::mt19937_64 rng(2026);
    std::uniform_int_distribution<int> joint(0, n - 1);
    std::uniform_real_distribution<double> jitter(0.0, 1.0);
    int detected = 0, collisions = 0, false_pushed = 0;
    double worst_delay = 0.0;
    for (int file = 0; file < 10; ++file) {
      SimulateRequest r = motion(truth, 60.0, 100 + file, 0.1 * file);
      for (int c = 0; c < 10; ++c) {
        Disturbance d;
        d.joint = joint(rng);
        d.torque = jitter(rng) < 0.5 ? -10.0 : 10.0;
        d.start = 5.0 + 5.0 * c + jitter(rng);
        d.duration = 0.1;
        r.simulation.seed = 100 + file;
        r.disturbances.push_back(d);
      }
      const SimulateOutcome pushed = simulateRun(r);
      const std::string data = benchDir() + "/" + tag + "_pushed.csv",
                        truth_file = benchDir() + "/" + tag + "_pushed.truth.csv";
      writeDatasetCsv(data, pushed.trajectory);
      writeExternalTorqueCsv(truth_file, pushed.trajectory.time, pushed.external);
      MonitorRequest m;
      m.arm = arm;
      m.data_file = data;
      m.calibration_file = calibration;
      m.truth_file = truth_file;
      const MonitorOutcome o = monitorRun(m);
      collisions += o.truth->episodes;
      detected += o.truth->detected;
      false_pushed += o.truth->false_alarms;
      for (double delay : o.truth->delays) worst_delay = std::max(worst_delay, delay);
    }
    // An hour of clean motion: 60 logs of 60 s, other seeds and phases.
    MonitorRequest clean;
    clean.arm = arm;
    clean.calibration_file = calibration;
    int false_alarms = 0;
    Eigen::VectorXd identified_thresholds, prior_thresholds;
    for (int file = 0; file < 60; ++file) {
      clean.data_file = logFile(motion(truth, 60.0, 1000 + file, 0.05 * file), tag + "_clean");
      const MonitorOutcome o = monitorRun(clean);
      false_alarms += static_cast<int>(o.events.size());
      identified_thresholds = o.thresholds.values;
    }
    MonitorRequest prior = clean;
    prior.arm = prior_spec;
    prior_thresholds = monitorRun(prior).thresholds.values;
    const Eigen::VectorXd ratio = prior_thresholds.cwiseQuotient(identified_thresholds);
    state.counters["detected_pct"] = 100.0 * detected / collisions;
    state.counters["worst_delay_ms"] = 1e3 * worst_delay;
    state.counters["false_alarms_hour"] = false_alarms;
    state.counters["false_alarms_pushed_logs"] = false_pushed;
    state.counters["prior_over_identified_min"] = ratio.minCoeff();
    std::printf(
        "\n%s: %d of %d collisions (10 N m, 0.1 s) detected within 50 ms, worst delay "
        "%.1f ms; %d false alarms in the pushed logs, %d in one hour of clean motion\n",
        tag.c_str(), detected, collisions, 1e3 * worst_delay, false_pushed, false_alarms);
    std::printf("  thresholds [N m], identified:");
    for (Eigen::Index j = 0; j < n; ++j) std::printf(" %.3g", identified_thresholds[j]);
    std::printf("\n  prior (nominal, no friction):");
    for (Eigen::Index j = 0; j < n; ++j) std::printf(" %.3g", prior_thresholds[j]);
    std::printf("\n  prior / identified:");
    for (Eigen::Index j = 0; j < n; ++j) std::printf(" %.2f", ratio[j]);
    std::printf("\n");
  }
}
BENCHMARK_CAPTURE(BM_MonitorAcceptance, puma560, makePuma560(true), "puma560")
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_MonitorAcceptance, panda, makePanda(true), "panda")
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

// ---- the arm states: pushes at rest and in motion, at the default rate ----

/// The truth of BM_MonitorStates: `nominal` perturbed by up to 20 % (seeded), with friction the
/// identification does not know exactly: Fv (per rad/s) and Fc each 1 % of the joint's peak torque
/// in the motion, and a Stribeck (breakaway) term half Fc that no identified model carries.
Model statesTruth(const Model& nominal, double bandwidth) {
  Model truth = perturbedModel(nominal, 0.2, 5);
  Model rigid = truth;
  rigid.setDriveTerms(DriveTerms::none());
  SimulateRequest r = motion(rigid, 10.0, 1, 0.0);
  r.bandwidth = bandwidth;
  const Trajectory reference = simulateRun(r).trajectory;
  DriveTerms terms = nominal.driveTerms();
  terms.mask |= DriveTerms::of({DriveTerm::kStribeck}).mask;
  truth.setDriveTerms(terms);
  for (int j = 0; j < truth.numJoints(); ++j) {
    const double scale = 0.01 * reference.tau.row(j).cwiseAbs().maxCoeff();
    DriveParameters<double> d = truth.drives()[j];
    d[DriveTerm::kViscous] = scale;
    d[DriveTerm::kCoulomb] = scale;
    d[DriveTerm::kStribeck] = 0.5 * scale;
    d[DriveTerm::kCoulombAsymmetry] = 0.0;
    truth.setDrive(j, d);
  }
  return truth;
}

/// A log of `seconds` with stops: `move` s of motion, then `hold` s at rest, over and over.
SimulateRequest pausedMotion(const Model& truth, double seconds, std::uint64_t seed, double phase,
                             double move, double hold, double bandwidth, bool stiction = false) {
  SimulateRequest r = motion(truth, seconds, seed, phase);
  r.bandwidth = bandwidth;
  r.simulation.stiction = stiction;
  Pauses p;
  p.move = move, p.hold = hold, p.ramp = 0.5;
  r.pauses = p;
  return r;
}

struct StatesScore {
  int rest_pushes = 0, rest_found = 0, moving_pushes = 0, moving_found = 0, false_alarms = 0;
  int rest_found_during = 0;  // an event started while the push at rest lasted
  /// With stiction: pushes at rest the static friction held (every recorded signal the same, bit
  /// for bit, as without the push), and those of the others found while they lasted.
  int rest_held = 0, rest_moved_found_during = 0;
  double seconds = 0.0;
};

/// What the push `which` of `r` changed in the recorded samples (noise included) from its start to
/// 0.5 s after its end, against the same run without it: the largest change of a torque [N m] and
/// of a position [rad]. Held: a push the joint's static friction held, which nothing recorded can
/// show (under 1e-9 N m and 1e-12 rad: at most the round-off of a later stick decision).
struct PushTrace {
  double tau = 0.0, q = 0.0;
  bool held() const { return tau < 1e-9 && q < 1e-12; }
};
PushTrace pushTrace(const SimulateRequest& r, std::size_t which, const Trajectory& pushed) {
  SimulateRequest without = r;
  without.disturbances.erase(without.disturbances.begin() + static_cast<std::ptrdiff_t>(which));
  const Trajectory other = simulateRun(without).trajectory;
  const Disturbance& d = r.disturbances[which];
  PushTrace out;
  for (int k = 0; k < pushed.numSamples(); ++k) {
    if (pushed.time[k] < d.start || pushed.time[k] > d.start + d.duration + 0.5) continue;
    out.tau = std::max(out.tau, (pushed.tau.col(k) - other.tau.col(k)).cwiseAbs().maxCoeff());
    out.q = std::max(out.q, (pushed.q.col(k) - other.q.col(k)).cwiseAbs().maxCoeff());
  }
  return out;
}

/// Pushes at rest (5 sigma_tau = 0.5 N m for 0.2 s, in the holds) and in motion (10 N m for 0.1 s),
/// random joint and sign, monitored with `thresholds` (a calibration, or a file); found: an event
/// starts within 50 ms.
void scorePushes(const Model& truth, const std::string& arm, const std::string& tag,
                 const MonitorRequest& base, int files, double bandwidth, bool stiction,
                 StatesScore& score) {
  const int n = truth.numJoints();
  std::mt19937_64 rng(2027);
  std::uniform_int_distribution<int> joint(0, n - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int file = 0; file < files; ++file) {
    // Cycles of 7 s: 3 s of motion (full speed from 0.5 to 2.5 s), 4 s at rest.
    SimulateRequest r =
        pausedMotion(truth, 56.0, 200 + file, 0.13 * file, 3.0, 4.0, bandwidth, stiction);
    for (int c = 0; c < 8; ++c) {
      Disturbance rest, moving;
      rest.joint = joint(rng), moving.joint = joint(rng);
      rest.torque = (unit(rng) < 0.5 ? -5.0 : 5.0) * r.simulation.noise_tau;
      moving.torque = unit(rng) < 0.5 ? -10.0 : 10.0;
      rest.start = 7.0 * c + 3.8 + 2.5 * unit(rng), rest.duration = 0.2;
      moving.start = 7.0 * c + 0.7 + 1.5 * unit(rng), moving.duration = 0.1;
      r.disturbances.push_back(moving);
      r.disturbances.push_back(rest);
    }
    const SimulateOutcome pushed = simulateRun(r);
    const std::string data = benchDir() + "/" + tag + "_states_pushed.csv";
    const std::string truth_file = benchDir() + "/" + tag + "_states_pushed.truth.csv";
    writeDatasetCsv(data, pushed.trajectory);
    writeExternalTorqueCsv(truth_file, pushed.trajectory.time, pushed.external);
    MonitorRequest m = base;
    m.arm = arm;
    m.data_file = data;
    m.truth_file = truth_file;
    const MonitorOutcome o = monitorRun(m);
    score.false_alarms += o.truth->false_alarms;
    for (const MonitorEvent& e : o.events) {
      const bool explained =
          std::any_of(r.disturbances.begin(), r.disturbances.end(), [&](const Disturbance& d) {
            return e.end >= d.start && e.start <= d.start + d.duration + 0.05;
          });
      if (!explained)
        std::printf(
            "  false alarm in a pushed log: log %d, t = %.3f..%.3f s, %s, joint %d, peak "
            "%.3g N m\n",
            file, e.start, e.end, e.at_rest ? "at rest" : "moving", e.peak_joint + 1, e.peak);
    }
    score.seconds += o.seconds;
    for (std::size_t which = 0; which < r.disturbances.size(); ++which) {
      const Disturbance& d = r.disturbances[which];
      const bool missed = std::any_of(o.truth->missed_starts.begin(), o.truth->missed_starts.end(),
                                      [&](double s) { return std::abs(s - d.start) < 2e-3; });
      const bool rest = d.duration > 0.15;
      const bool during = std::any_of(o.events.begin(), o.events.end(), [&](const MonitorEvent& e) {
        return e.start >= d.start - 1e-9 && e.start <= d.start + d.duration;
      });
      const PushTrace trace =
          rest && stiction ? pushTrace(r, which, pushed.trajectory) : PushTrace{1.0, 1.0};
      const bool held = trace.held();
      if (rest) score.rest_found_during += during ? 1 : 0;
      score.rest_held += held ? 1 : 0;
      if (rest && !held) score.rest_moved_found_during += during ? 1 : 0;
      if (!during && rest && stiction)
        std::printf(
            "  not found at rest: log %d, joint %d, %.3g N m at %.3f s: %s (torques changed by up "
            "to %.3g N m, positions by %.3g rad)\n",
            file, d.joint + 1, d.torque, d.start,
            held ? "held by its static friction, nothing recorded changed" : "it slipped",
            trace.tau, trace.q);
      else if (!during && rest)
        std::printf("  not found at rest: log %d, joint %d, %.3g N m at %.3f s\n", file,
                    d.joint + 1, d.torque, d.start);
      (rest ? score.rest_pushes : score.moving_pushes) += 1;
      (rest ? score.rest_found : score.moving_found) += missed ? 0 : 1;
    }
  }
}

void BM_MonitorStates(benchmark::State& state, const Model& nominal_drives, bool stiction) {
  for (auto _ : state) {
    // A stiff controller (20 Hz): at 2-5 Hz the simulated Panda hunts around its holds.
    const double bandwidth = 20.0;
    const Model truth = statesTruth(nominal_drives, bandwidth);
    const std::string tag = truth.name;
    writeFileAtomically(benchDir() + "/" + tag + "_states_truth.json", modelToJson(truth));
    const std::string arm = benchDir() + "/" + tag + "_states_identified.json";
    SimulateRequest training = motion(truth, 60.0, 11, 0.3);
    training.bandwidth = bandwidth;
    training.simulation.stiction = stiction;
    writeFileAtomically(
        arm, modelToJson(identified(nominal_drives, logFile(training, tag + "_states_train"))));
    // Calibrated on another motion than the one watched: 4 s moves, 3 s holds, another phase.
    MonitorRequest calibrated;
    calibrated.calibration_file =
        logFile(pausedMotion(truth, 120.0, 12, 0.7, 4.0, 3.0, bandwidth, stiction),
                tag + "_states_calibration");
    StatesScore now, before;
    scorePushes(truth, arm, tag, calibrated, 10, bandwidth, stiction, now);
    // The previous release: the same thresholds for the moving arm, none at rest.
    MonitorRequest clean = calibrated;
    clean.arm = arm;
    clean.data_file = calibrated.calibration_file;
    const MonitorThresholds thresholds = monitorRun(clean).thresholds;
    MonitorRequest previous;
    previous.thresholds_file =
        test::writeThresholdsWithoutStates(thresholds, benchDir() + "/" + tag + "_v1.json");
    scorePushes(truth, arm, tag, previous, 10, bandwidth, stiction, before);
    // An hour of clean motion with stops: 60 logs of 60 s, other seeds and phases.
    int clean_alarms = 0, clean_alarms_before = 0;
    for (int file = 0; file < 60; ++file) {
      clean.data_file = logFile(pausedMotion(truth, 60.0, 3000 + file, 0.05 * file,
                                             3.0 + 0.05 * file, 2.0, bandwidth, stiction),
                                tag + "_states_clean");
      const MonitorOutcome o = monitorRun(clean);
      clean_alarms += static_cast<int>(o.events.size());
      for (const MonitorEvent& e : o.events)  // what raised it: where, in which state
        std::printf("  false alarm: log %d, t = %.3f s, %s, joint %d, peak %.3g N m\n", file,
                    e.start, e.at_rest ? "at rest" : "moving", e.peak_joint + 1, e.peak);
      MonitorRequest old = previous;
      old.arm = arm;
      old.data_file = clean.data_file;
      clean_alarms_before += static_cast<int>(monitorRun(old).events.size());
    }
    state.counters["rest_found_pct"] = 100.0 * now.rest_found / now.rest_pushes;
    state.counters["rest_found_during_pct"] = 100.0 * now.rest_found_during / now.rest_pushes;
    state.counters["moving_found_pct"] = 100.0 * now.moving_found / now.moving_pushes;
    state.counters["false_alarms_hour"] = clean_alarms;
    std::printf("\n%s, %s false alarms per hour (the default):\n", tag.c_str(),
                formatNumber(kDefaultFalseAlarmsPerHour, 3).c_str());
    const auto line = [](const char* who, const StatesScore& s, int clean_hour) {
      std::printf(
          "  %s: pushes at rest (0.5 N m, 0.2 s) %d of %d found within 50 ms, %d while they "
          "lasted; in motion (10 N m, 0.1 s) %d of %d within 50 ms; false alarms %d in the pushed "
          "logs, %d in one hour of clean motion with stops\n",
          who, s.rest_found, s.rest_pushes, s.rest_found_during, s.moving_found, s.moving_pushes,
          s.false_alarms, clean_hour);
    };
    line("arm states", now, clean_alarms);
    if (stiction)
      std::printf(
          "  with stiction: %d of %d pushes at rest held by the joint's static friction (nothing "
          "recorded changed); of the %d others, %d found while they lasted\n",
          now.rest_held, now.rest_pushes, now.rest_pushes - now.rest_held,
          now.rest_moved_found_during);
    line("previous release (no thresholds at rest)", before, clean_alarms_before);
    std::printf("  thresholds [N m], moving:");
    for (Eigen::Index j = 0; j < thresholds.values.size(); ++j)
      std::printf(" %.3g", thresholds.values[j]);
    std::printf("\n  at rest:");
    for (Eigen::Index j = 0; j < thresholds.values_at_rest.size(); ++j)
      std::printf(" %.3g", thresholds.values_at_rest[j]);
    std::printf("\n  calibration at rest: %.1f s of 120\n", thresholds.rest_seconds);
  }
}
BENCHMARK_CAPTURE(BM_MonitorStates, puma560, makePuma560(true), false)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_MonitorStates, panda, makePanda(true), false)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
// The same with stick-slip friction in the truth (SimulationOptions::stiction): a resting joint
// held by its static friction, as a real arm's is.
BENCHMARK_CAPTURE(BM_MonitorStates, puma560_stiction, makePuma560(true), true)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_MonitorStates, panda_stiction, makePanda(true), true)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

// ---- the moving regimes: pushes in motion near the moving thresholds ----

struct MovingScore {
  int pushes = 0, found = 0, false_alarms = 0;
  std::vector<int> found_by_regime = std::vector<int>(kMovingRegimes, 0);
};

/// Pushes in motion of `size` times each joint's single moving threshold for 0.1 s (8 per log,
/// in the moves, random joint and sign; the same pushes for every `thresholds` file), found when an
/// event starts within 50 ms; per file of `thresholds`, a score.
void scoreMovingPushes(const Model& truth, const std::string& arm, const std::string& tag,
                       const Eigen::VectorXd& single, double size,
                       const std::vector<std::string>& thresholds, int files, double bandwidth,
                       std::vector<MovingScore>& scores) {
  const int n = truth.numJoints();
  std::mt19937_64 rng(2028);
  std::uniform_int_distribution<int> joint(0, n - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int file = 0; file < files; ++file) {
    SimulateRequest r = pausedMotion(truth, 56.0, 400 + file, 0.17 * file, 3.0, 4.0, bandwidth);
    for (int c = 0; c < 8; ++c) {
      Disturbance d;
      d.joint = joint(rng);
      d.torque = (unit(rng) < 0.5 ? -size : size) * single[d.joint];
      d.start = 7.0 * c + 0.2 + 2.6 * unit(rng), d.duration = 0.1;
      r.disturbances.push_back(d);
    }
    const SimulateOutcome pushed = simulateRun(r);
    const std::string data = benchDir() + "/" + tag + "_regimes_pushed.csv";
    const std::string truth_file = benchDir() + "/" + tag + "_regimes_pushed.truth.csv";
    writeDatasetCsv(data, pushed.trajectory);
    writeExternalTorqueCsv(truth_file, pushed.trajectory.time, pushed.external);
    for (std::size_t i = 0; i < thresholds.size(); ++i) {
      MonitorRequest m;
      m.arm = arm;
      m.data_file = data;
      m.truth_file = truth_file;
      m.thresholds_file = thresholds[i];
      const MonitorOutcome o = monitorRun(m);
      scores[i].pushes += o.truth->episodes;
      scores[i].found += o.truth->detected;
      scores[i].false_alarms += o.truth->false_alarms;
      for (const MonitorEvent& e : o.events)
        if (e.peak_regime >= 0) scores[i].found_by_regime[e.peak_regime] += 1;
    }
  }
}

/// `nominal` perturbed by up to 20 % (seeded) with its own (published) drive model and a Stribeck
/// term half its Coulomb friction that no identified model carries: friction whose sign errors at
/// reversals dominate the moving residual, as on a geared arm.
Model publishedTruth(const Model& nominal) {
  Model truth = perturbedModel(nominal, 0.2, 5);  // its inertia; the drives are the nominal's
  const Model drives = test::withStribeck(nominal);
  truth.setDriveTerms(drives.driveTerms());
  for (int j = 0; j < truth.numJoints(); ++j) truth.setDrive(j, drives.drives()[j]);
  return truth;
}

void BM_MonitorRegimes(benchmark::State& state, const Model& nominal_drives, bool published) {
  for (auto _ : state) {
    const double bandwidth = 20.0;  // as BM_MonitorStates
    const Model truth =
        published ? publishedTruth(nominal_drives) : statesTruth(nominal_drives, bandwidth);
    const std::string tag = truth.name + (published ? "_published" : "");
    const std::string arm = benchDir() + "/" + tag + "_regimes_identified.json";
    SimulateRequest training = motion(truth, 60.0, 11, 0.3);
    training.bandwidth = bandwidth;
    writeFileAtomically(
        arm, modelToJson(identified(nominal_drives, logFile(training, tag + "_regimes_train"))));
    // Calibrated on another motion than the one watched, as BM_MonitorStates.
    MonitorRequest clean;
    clean.arm = arm;
    clean.calibration_file = logFile(pausedMotion(truth, 120.0, 12, 0.7, 4.0, 3.0, bandwidth),
                                     tag + "_regimes_calibration");
    clean.data_file = clean.calibration_file;
    const MonitorThresholds t = monitorRun(clean).thresholds;
    const std::string with = benchDir() + "/" + tag + "_regimes_v3.json";
    writeFileAtomically(with, monitorThresholdsJson(t).dump());
    const std::vector<std::string> files = {
        with, test::writeThresholdsWithoutRegimes(t, benchDir() + "/" + tag + "_regimes_v2.json")};
    const std::vector<double> sizes = {0.5, 0.75, 1.0};
    std::vector<std::vector<MovingScore>> scores(sizes.size(),
                                                 std::vector<MovingScore>(files.size()));
    for (std::size_t k = 0; k < sizes.size(); ++k)
      scoreMovingPushes(truth, arm, tag, t.values, sizes[k], files, 10, bandwidth, scores[k]);
    // An hour of clean motion with stops (BM_MonitorStates's logs).
    std::vector<int> clean_alarms(files.size(), 0);
    for (int file = 0; file < 60; ++file) {
      const std::string data = logFile(
          pausedMotion(truth, 60.0, 3000 + file, 0.05 * file, 3.0 + 0.05 * file, 2.0, bandwidth),
          tag + "_regimes_clean");
      for (std::size_t i = 0; i < files.size(); ++i) {
        MonitorRequest m;
        m.arm = arm;
        m.data_file = data;
        m.thresholds_file = files[i];
        const MonitorOutcome o = monitorRun(m);
        clean_alarms[i] += static_cast<int>(o.events.size());
        for (const MonitorEvent& e : o.events)
          std::printf("  false alarm (%s): log %d, t = %.3f s, %s, joint %d, peak %.3g N m\n",
                      i == 0 ? "regimes" : "one moving threshold", file, e.start,
                      e.at_rest ? "at rest" : kMovingRegimeNames[std::max(e.peak_regime, 0)],
                      e.peak_joint + 1, e.peak);
      }
    }
    state.counters["found_075x_pct"] = 100.0 * scores[1][0].found / scores[1][0].pushes;
    state.counters["found_075x_before_pct"] = 100.0 * scores[1][1].found / scores[1][1].pushes;
    state.counters["false_alarms_hour"] = clean_alarms[0];
    std::printf("\n%s, %s false alarms per hour (the default):\n", tag.c_str(),
                formatNumber(kDefaultFalseAlarmsPerHour, 3).c_str());
    for (std::size_t k = 0; k < sizes.size(); ++k)
      for (std::size_t i = 0; i < files.size(); ++i)
        std::printf(
            "  %s: pushes in motion of %.2g x the joint's single moving threshold (0.1 s) %d of %d "
            "found within 50 ms; false alarms %d in the pushed logs\n",
            i == 0 ? "moving regimes" : "one moving threshold", sizes[k], scores[k][i].found,
            scores[k][i].pushes, scores[k][i].false_alarms);
    std::printf("  false alarms in one hour of clean motion with stops: %d (regimes), %d (one)\n",
                clean_alarms[0], clean_alarms[1]);
    std::printf("  single moving thresholds [N m]:");
    for (Eigen::Index j = 0; j < t.values.size(); ++j) std::printf(" %.3g", t.values[j]);
    std::printf("\n  per regime (threshold / single; seconds of calibration):\n");
    for (int c = 0; c < kMovingRegimes; ++c) {
      std::printf("    %-22s", kMovingRegimeNames[c]);
      for (Eigen::Index j = 0; j < t.values.size(); ++j)
        std::printf(" %5.2f (%4.1f s)",
                    t.values_by_regime(j, c) > 0.0 ? t.values_by_regime(j, c) / t.values[j] : 0.0,
                    t.regime_seconds(j, c));
      std::printf("\n");
    }
  }
}
BENCHMARK_CAPTURE(BM_MonitorRegimes, puma560, makePuma560(true), false)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_MonitorRegimes, panda, makePanda(true), false)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_MonitorRegimes, puma560_published, makePuma560(true), true)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace
}  // namespace dynid

BENCHMARK_MAIN();
