// dynid monitor: its speed, and its acceptance in simulation (docs/MONITOR.md, "Measured").
//   - BM_ObserverSample/<robot>: one sample of the momentum observer (p = M dq, beta, the update).
//   - BM_MonitorFile/csv: monitorRun on a 60 s, 1 kHz Panda log file (CSV parsing included); its
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
#include "core/momentum.hpp"
#include "core/perturb.hpp"
#include "data/dataset_csv.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "tests/common/joint_state_db3.hpp"

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
  const std::string thresholds = benchDir() + "/speed_thresholds.json";
  {
    // The thresholds document monitor writes (reports/), read back through --thresholds.
    nlohmann::json t = {{"schema_version", 1},
                        {"kind", "dynid.monitor_thresholds"},
                        {"robot", panda.name},
                        {"joints", panda.joint_names},
                        {"residual", "observer"},
                        {"gain", std::vector<double>(7, 100.0)},
                        {"thresholds", std::vector<double>(first.thresholds.values.data(),
                                                           first.thresholds.values.data() + 7)},
                        {"source", "bench"}};
    writeFileAtomically(thresholds, t.dump());
  }
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

}  // namespace
}  // namespace dynid

BENCHMARK_MAIN();
