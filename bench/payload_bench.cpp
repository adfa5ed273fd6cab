// dynid payload's acceptance in simulation (docs/PAYLOAD.md, "Accuracy"): on the PUMA 560 and the
// Panda, 24 payloads (0.2 to 5 kg, centres of mass up to 0.15 m from the flange, boxes of random
// aspect, density and orientation: asymmetric inertias with products), a 15 s payload motion
// designed by `dynid excite --payload` (d-optimal), sampled at 1 kHz, white torque noise per joint
// at the real Panda log's OLS residual RMS (examples/panda: 0.118, 0.108, 0.116, 0.138, 0.083,
// 0.058, 0.066 N m; the PUMA takes the first six), 5 noise seeds per payload. Every case runs
// payloadRun end to end on CSV files, as the CLI does. Reported:
//   - truth arm, one log: mass, centre-of-mass and inertia errors (max and median), how often the
//     95 % intervals cover the truth (mass, centre of mass, inertia about it), consistency;
//   - the arm identified by OLS from a noisy 30 s unloaded log: one log against the
//     loaded-minus-unloaded difference (seed 1 of each payload);
//   - drive gains from the known mass (friction on, gains 0.9 to 1.1): the worst scale error.
// and on light tools (10 g to 1 kg, BM_LightTools*): whether what dynid marks determined is within
// its interval and 25 % of its value, and how much it reports as not determined.
// Run: build/bench/bench_payload  (about 2 minutes on 2 cores; counters and a table on stdout).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Geometry>

#include "analysis/excitation/excite.hpp"
#include "analysis/excitation/limits.hpp"
#include "analysis/payload/body.hpp"
#include "analysis/payload/payload.hpp"
#include "core/parameters.hpp"
#include "core/rnea.hpp"
#include "data/dataset_csv.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares_stream.hpp"

namespace {

using namespace dynid;

const double kNoise[7] = {0.118, 0.108, 0.116, 0.138, 0.083, 0.058, 0.066};

std::vector<PrincipalBody> payloadSet(double lightest = 0.2, double heaviest = 5.0) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<PrincipalBody> out;
  for (int i = 0; i < 24; ++i) {
    PrincipalBody b;
    // lightest .. heaviest (0.2 .. 5 kg by default), spread evenly in log
    b.mass = lightest * std::pow(heaviest / lightest, (i + u(rng)) / 24.0);
    const double density = 1500.0 + 1500.0 * u(rng);
    Eigen::Vector3d aspect(0.5 + 1.5 * u(rng), 0.5 + 1.5 * u(rng), 0.5 + 1.5 * u(rng));
    aspect *= std::cbrt(b.mass / density / aspect.prod());  // box sides [m]
    const Eigen::Vector3d s = aspect.cwiseAbs2();
    b.moments = b.mass / 12.0 * Eigen::Vector3d(s.y() + s.z(), s.x() + s.z(), s.x() + s.y());
    Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
    b.axes = q.normalized().toRotationMatrix();
    Eigen::Vector3d d(normal(rng), normal(rng), normal(rng));
    b.com = d.normalized() * 0.15 * u(rng);
    out.push_back(b);
  }
  return out;
}

Model withPayload(const Model& arm, const Pose<double>& tool, const Vector10d& body) {
  Model out = arm;
  const int link = arm.numJoints() - 1;
  RigidInertia<double> inertia = arm.inertias()[link];
  inertia += fromStandardVector(body).transformedBy(tool);
  out.setLinkInertia(link, inertia);
  return out;
}

std::string logFile(const Model& model, Trajectory t, const std::string& name, std::uint64_t seed,
                    const Eigen::VectorXd& gain = {}) {
  Data data(model);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int k = 0; k < t.numSamples(); ++k) {
    t.tau.col(k) = rnea(model, data, t.q.col(k), t.dq.col(k), t.ddq.col(k));
    for (int j = 0; j < model.numJoints(); ++j) {
      if (gain.size() > 0) t.tau(j, k) /= gain[j];
      t.tau(j, k) += kNoise[j] * normal(rng);
    }
  }
  const std::string path = "/tmp/dynid_bench_payload_" + name + ".csv";
  writeDatasetCsv(path, t);
  return path;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

struct Errors {
  std::vector<double> mass, com, inertia;
  std::vector<double> inertia_determined;  // where dynid reports every principal moment determined
  std::vector<double> inertia_heavy;       // payloads of 1 kg and more
  void add(const PayloadOutcome& o, const PrincipalBody& truth) {
    mass.push_back(100.0 * std::abs(o.mass - truth.mass) / truth.mass);
    com.push_back(1e3 * (o.com - truth.com).norm());
    const Eigen::Matrix3d ic = truth.axes * truth.moments.asDiagonal() * truth.axes.transpose();
    const double e = 100.0 * (o.inertia_com - ic).norm() / ic.norm();
    inertia.push_back(e);
    bool determined = true;
    for (const PayloadQuantity& q : o.quantities)
      if (q.group == "principal moments" && !q.determined) determined = false;
    if (determined) inertia_determined.push_back(e);
    if (truth.mass >= 1.0) inertia_heavy.push_back(e);
  }
};

/// The 15 s d-optimal payload motion `dynid excite --payload` designs for the last link, at 1 kHz.
Trajectory payloadMotion(const Model& arm) {
  ExciteRequest excite;
  excite.robot = arm;
  excite.limits = excitationLimits(arm, {});
  excite.payload_link = arm.numJoints() - 1;
  excite.period = 15.0;
  excite.criterion = ExcitationCriterion::kDOptimal;
  excite.threads = 0;
  return sampleFourier(exciteRun(excite).design, arm, 1000.0);
}

void runRobot(benchmark::State& state, const Model& arm, const Model& arm_with_drives,
              const Pose<double>& tool) {
  const int n = arm.numJoints();
  for (auto _ : state) {
    const Trajectory motion = payloadMotion(arm);
    const std::vector<PrincipalBody> set = payloadSet();

    // 1. The truth arm, one log, 5 seeds per payload.
    Errors truth_arm;
    int covered[3] = {0, 0, 0}, counted[3] = {0, 0, 0}, inconsistent = 0, cases = 0;
    for (std::size_t i = 0; i < set.size(); ++i)
      for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        const Vector10d body = standardFromPrincipal(set[i]);
        PayloadRequest r;
        r.arm = arm;
        r.tool = tool;
        r.data_file = logFile(withPayload(arm, tool, body), motion, "loaded", 100 * i + seed);
        const PayloadOutcome o = payloadRun(r);
        truth_arm.add(o, set[i]);
        ++cases;
        if (!checkPhysicalConsistency(fromStandardVector(o.standard), 0, "p").empty())
          ++inconsistent;
        const Eigen::Matrix3d ic =
            set[i].axes * set[i].moments.asDiagonal() * set[i].axes.transpose();
        const double truth_values[10] = {
            set[i].mass, set[i].com.x(), set[i].com.y(), set[i].com.z(), ic(0, 0),
            ic(0, 1),    ic(0, 2),       ic(1, 1),       ic(1, 2),       ic(2, 2)};
        for (int k = 0; k < 10; ++k) {
          const int group = k == 0 ? 0 : k <= 3 ? 1 : 2;
          ++counted[group];
          covered[group] +=
              std::abs(o.quantities[k].value - truth_values[k]) <= o.quantities[k].half_width;
        }
      }

    // 2. The arm identified by OLS from a noisy unloaded log (30 s of the default sinusoid).
    Trajectory id_motion;
    {
      const SinusoidalReference sinusoid = defaultSinusoid(arm);
      const int samples = 30001;
      id_motion.resize(n, samples);
      Eigen::VectorXd q(n), dq(n), ddq(n);
      for (int k = 0; k < samples; ++k) {
        id_motion.time[k] = k * 1e-3;
        evaluateReference(sinusoid, id_motion.time[k], q, dq, ddq);
        id_motion.q.col(k) = q;
        id_motion.dq.col(k) = dq;
        id_motion.ddq.col(k) = ddq;
      }
    }
    const Trajectory id_log = readDatasetCsv(logFile(arm, id_motion, "identify", 7), n);
    const BaseParameters base = structuralBaseParameters(arm);
    LeastSquaresStream stream(base, arm);
    stream.addTrajectory(arm, id_log);
    Model identified = arm;
    identified.setStandardParameters(base.standardFromBase(
        stream.estimate(LeastSquaresMethod::kOrdinary).beta, arm.standardParameters()));
    Errors single, difference;
    for (std::size_t i = 0; i < set.size(); ++i) {
      const Vector10d body = standardFromPrincipal(set[i]);
      PayloadRequest r;
      r.arm = identified;
      r.tool = tool;
      r.data_file = logFile(withPayload(arm, tool, body), motion, "loaded", 100 * i + 1);
      single.add(payloadRun(r), set[i]);
      r.unloaded_file = logFile(arm, motion, "unloaded", 100 * i + 51);
      difference.add(payloadRun(r), set[i]);
    }

    // 3. Drive gains from the known mass, the arm with friction.
    double worst_gain = 0.0, worst_gain_heavy = 0.0;
    int undetermined = 0;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> g(0.9, 1.1);
    for (std::size_t i = 0; i < set.size(); ++i) {
      Eigen::VectorXd gain(n);
      for (int j = 0; j < n; ++j) gain[j] = g(rng);
      const Vector10d body = standardFromPrincipal(set[i]);
      PayloadRequest r;
      r.arm = arm_with_drives;
      r.tool = tool;
      r.known_mass = set[i].mass;
      r.data_file = logFile(withPayload(arm_with_drives, tool, body), motion, "gain_loaded",
                            100 * i + 1, gain);
      r.unloaded_file = logFile(arm_with_drives, motion, "gain_unloaded", 100 * i + 51, gain);
      const PayloadOutcome o = payloadRun(r);
      for (int j = 0; j < n; ++j) {
        if (!o.gains->determined[j]) {
          ++undetermined;
          continue;
        }
        const double e = 100.0 * std::abs(o.gains->scale[j] / gain[j] - 1.0);
        worst_gain = std::max(worst_gain, e);
        if (set[i].mass >= 2.0) worst_gain_heavy = std::max(worst_gain_heavy, e);
      }
    }

    const auto max = [](const std::vector<double>& v) {
      return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
    };
    state.counters["mass_err_max_pct"] = max(truth_arm.mass);
    state.counters["com_err_max_mm"] = max(truth_arm.com);
    state.counters["inertia_err_max_pct"] = max(truth_arm.inertia);
    state.counters["cover_mass_pct"] = 100.0 * covered[0] / counted[0];
    state.counters["cover_com_pct"] = 100.0 * covered[1] / counted[1];
    state.counters["cover_inertia_pct"] = 100.0 * covered[2] / counted[2];
    state.counters["inconsistent"] = inconsistent;
    state.counters["id_single_mass_max_pct"] = max(single.mass);
    state.counters["id_diff_mass_max_pct"] = max(difference.mass);
    state.counters["inertia_determined_err_max_pct"] = max(truth_arm.inertia_determined);
    state.counters["inertia_1kg_err_max_pct"] = max(truth_arm.inertia_heavy);
    state.counters["gain_err_max_pct"] = worst_gain;
    state.counters["gain_2kg_err_max_pct"] = worst_gain_heavy;
    state.counters["gain_undetermined"] = undetermined;
    std::printf(
        "\n%s: %d cases (24 payloads x 5 seeds), truth arm, one log\n"
        "  mass error      max %.3f %%  median %.3f %%\n"
        "  COM error       max %.3f mm median %.3f mm\n"
        "  inertia (COM)   max %.2f %%  median %.2f %% (relative Frobenius)\n"
        "                  where reported determined (%zu cases): max %.2f %%; payloads >= 1 kg "
        "(%zu cases): max %.2f %%\n"
        "  95 %% coverage   mass %.1f %%, COM %.1f %%, inertia %.1f %%; inconsistent: %d\n"
        "arm identified by OLS (30 s noisy log), 24 payloads:\n"
        "  one log:        mass max %.3f %% median %.3f %%, COM max %.2f mm, inertia max %.1f %%\n"
        "  difference:     mass max %.3f %% median %.3f %%, COM max %.2f mm, inertia max %.1f %%\n"
        "drive gains from the known mass (24 payloads, gains 0.9..1.1): worst %.3f %% "
        "(%d joint x payload cases not determined); payloads >= 2 kg: worst %.3f %%\n",
        arm.name.c_str(), cases, max(truth_arm.mass), median(truth_arm.mass), max(truth_arm.com),
        median(truth_arm.com), max(truth_arm.inertia), median(truth_arm.inertia),
        truth_arm.inertia_determined.size(), max(truth_arm.inertia_determined),
        truth_arm.inertia_heavy.size(), max(truth_arm.inertia_heavy),
        100.0 * covered[0] / counted[0], 100.0 * covered[1] / counted[1],
        100.0 * covered[2] / counted[2], inconsistent, max(single.mass), median(single.mass),
        max(single.com), max(single.inertia), max(difference.mass), median(difference.mass),
        max(difference.com), max(difference.inertia), worst_gain, undetermined, worst_gain_heavy);
  }
}

/// The 13 derived quantities of a body (payloadRun's first 13: m, c, I_c's six entries, the
/// principal moments in ascending order).
std::array<double, 13> derivedTruth(const PrincipalBody& b) {
  const Eigen::Matrix3d ic = b.axes * b.moments.asDiagonal() * b.axes.transpose();
  Eigen::Vector3d moments = b.moments;
  std::sort(moments.data(), moments.data() + 3);
  return {b.mass,   b.com.x(), b.com.y(), b.com.z(),  ic(0, 0),   ic(0, 1),  ic(0, 2),
          ic(1, 1), ic(1, 2),  ic(2, 2),  moments[0], moments[1], moments[2]};
}

/// Light tools (10 g to 1 kg), the truth arm, one log each, 5 seeds: of the derived quantities
/// dynid marks determined, how many lie within their 95 % interval and within 25 % of their value
/// (the mass and the principal moments; 25 % of the largest principal moment for an inertia
/// entry; 6.25 mm, 1.25 times the 5 mm rule, for a centre-of-mass coordinate); how many are
/// reported as not determined (their resolution instead of a number).
void runLightTools(benchmark::State& state, const Model& arm, const Pose<double>& tool) {
  for (auto _ : state) {
    const Trajectory motion = payloadMotion(arm);
    const std::vector<PrincipalBody> set = payloadSet(0.01, 1.0);
    int determined = 0, covered = 0, within = 0, undetermined = 0, cases = 0;
    double worst = 0.0;  // the largest error of a determined quantity, in its 25 % bound
    std::string worst_name;
    for (std::size_t i = 0; i < set.size(); ++i)
      for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        PayloadRequest r;
        r.arm = arm;
        r.tool = tool;
        r.data_file = logFile(withPayload(arm, tool, standardFromPrincipal(set[i])), motion,
                              "light", 100 * i + seed);
        const PayloadOutcome o = payloadRun(r);
        ++cases;
        const std::array<double, 13> truth = derivedTruth(set[i]);
        const double largest = std::max({truth[10], truth[11], truth[12]});
        // The principal moments come in the order of the axes nearest the attachment frame's:
        // matched to the truth's in ascending order.
        std::vector<PayloadQuantity> derived(o.quantities.begin(), o.quantities.begin() + 13);
        std::sort(
            derived.begin() + 10, derived.end(),
            [](const PayloadQuantity& a, const PayloadQuantity& b) { return a.value < b.value; });
        for (int k = 0; k < 13; ++k) {
          const PayloadQuantity& q = derived[static_cast<std::size_t>(k)];
          if (!q.determined) {
            ++undetermined;
            continue;
          }
          ++determined;
          const double error = std::abs(q.value - truth[static_cast<std::size_t>(k)]);
          covered += error <= q.half_width;
          const double bound = k == 0 || k >= 10
                                   ? 0.25 * std::abs(truth[static_cast<std::size_t>(k)])
                               : k <= 3 ? 6.25e-3
                                        : 0.25 * largest;
          within += error <= bound;
          if (error / bound > worst) {
            worst = error / bound;
            worst_name = q.name + " of " + std::to_string(set[i].mass) + " kg";
          }
        }
      }
    state.counters["determined"] = determined;
    state.counters["undetermined"] = undetermined;
    state.counters["cover_pct"] = 100.0 * covered / std::max(determined, 1);
    state.counters["within_25_pct"] = 100.0 * within / std::max(determined, 1);
    std::printf(
        "\n%s, light tools 0.01 .. 1 kg: %d cases x 13 quantities: %d determined (%.1f %% "
        "within their 95 %% interval, %.1f %% within 25 %%; the worst at %.2f of its bound: %s), "
        "%d reported as not determined\n",
        arm.name.c_str(), cases, determined, 100.0 * covered / std::max(determined, 1),
        100.0 * within / std::max(determined, 1), worst, worst_name.c_str(), undetermined);
  }
}

void BM_LightToolsPuma(benchmark::State& state) {
  Pose<double> flange;
  flange.translation = Eigen::Vector3d(0.0, 0.0, 0.05);
  runLightTools(state, makePuma560(false), flange);
}
void BM_LightToolsPanda(benchmark::State& state) {
  Pose<double> flange;
  flange.translation = Eigen::Vector3d(0.0, 0.0, 0.107);
  runLightTools(state, makePanda(false), flange);
}
BENCHMARK(BM_LightToolsPuma)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(BM_LightToolsPanda)->Iterations(1)->Unit(benchmark::kSecond);

void BM_PayloadPuma(benchmark::State& state) {
  Pose<double> flange;
  flange.translation = Eigen::Vector3d(0.0, 0.0, 0.05);
  runRobot(state, makePuma560(false), makePuma560(true), flange);
}
void BM_PayloadPanda(benchmark::State& state) {
  Pose<double> flange;  // Franka's flange frame F: 0.107 m along link 7's z
  flange.translation = Eigen::Vector3d(0.0, 0.0, 0.107);
  runRobot(state, makePanda(false), makePanda(true), flange);
}
BENCHMARK(BM_PayloadPuma)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(BM_PayloadPanda)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
