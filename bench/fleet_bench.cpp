// dynid fleet: its acceptance in simulation (docs/FLEET.md, "A fleet: measured").
//   - BM_FleetAcceptance: per seed, a fleet of 50 Pandas. The nominal Panda (data/panda.hpp, its
//     drive terms fv, fc, fo) with friction Fv = 0.4 N m s/rad and Fc = 0.4 N m on joints 1-4,
//     0.15 and 0.2 on 5-7; each robot's links' inertial parameters (all ten, so the centre of mass
//     and the inertia's shape stay) and its Fv and Fc each scaled by 1 + U(-5 %, 5 %). Robot 0
//     has +50 % Coulomb friction on joint 4; robot 1 carries an undeclared 1 kg tool 0.15 m
//     beyond the flange (link 7's frame, inertia 1e-3 kg m^2 about its centre). Robots 2-6 have
//     one 10 s log; the others ten 60 s logs. A log: a seeded Fourier motion (0.1 Hz, 5
//     harmonics, 0.7 rad about the middle of the limits) with stops (4 s moves, 2 s holds, 0.5 s
//     ramps), sampled at 200 Hz, q, dq, ddq exact and then noise of 0.1 N m on tau and 1e-3
//     rad/s on dq (so the arm at rest has velocities of noise, and the fit's rows at rest follow
//     runs/training.hpp as on a real log). Each log summarized in memory (runs/summarize.hpp),
//     the fleet by fleetRun (ols, hac, flag level 0.01). Reported over the seeds: the share in
//     which both odd robots are flagged and no other, the share with a false flag; for robots 2-6
//     the parameter error alone over the error with the prior (median over robots and seeds), the
//     error being the torque it makes on a reference motion (a nominal 60 s log's base regressor
//     W): |W (beta_hat - beta)| / |W beta|.
//   - BM_FleetAcceptance/stribeck: the same with a model error every robot shares: each truth also
//     has Stribeck friction, Fs = half its Fc on every joint, which the identified model (fv, fc,
//     fo) does not carry (at every stop and reversal).
// Run: build/bench/bench_fleet [--benchmark_filter=...]; DYNID_FLEET_SEEDS (default 20) seeds.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "analysis/fleet/fleet.hpp"
#include "analysis/runs/simulate.hpp"
#include "analysis/runs/summarize.hpp"
#include "core/controllers.hpp"
#include "core/data.hpp"
#include "core/regressor.hpp"
#include "data/panda.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "tests/common/fleet_logs.hpp"

namespace dynid {
namespace {

constexpr int kRobots = 50, kShortFirst = 2, kShortLast = 6;
constexpr double kRate = 200.0;

Model nominalPanda() {
  Model m = makePanda(true);
  Eigen::VectorXd theta = m.standardParameters();
  const ParameterLayout layout = m.parameterLayout();
  const DriveTerms d = m.driveTerms();
  for (int j = 0; j < m.numJoints(); ++j) {
    const int at = j * layout.perLink() + kLinkParameterCount;
    theta[at + d.column(static_cast<int>(DriveTerm::kViscous))] = j < 4 ? 0.4 : 0.15;
    theta[at + d.column(static_cast<int>(DriveTerm::kCoulomb))] = j < 4 ? 0.4 : 0.2;
  }
  m.setStandardParameters(theta);
  return m;
}

/// Robot r of the fleet: the nominal one varied by +-5 %, robots 0 and 1 odd.
Model fleetRobot(const Model& nominal, int r, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  Model m = nominal;
  Eigen::VectorXd theta = m.standardParameters();
  const ParameterLayout layout = m.parameterLayout();
  const DriveTerms d = m.driveTerms();
  const int fv = d.column(static_cast<int>(DriveTerm::kViscous));
  const int fc = d.column(static_cast<int>(DriveTerm::kCoulomb));
  for (int j = 0; j < m.numJoints(); ++j) {
    const int at = j * layout.perLink();
    theta.segment(at, kLinkParameterCount) *= 1.0 + u(rng);
    theta[at + kLinkParameterCount + fv] *= 1.0 + u(rng);
    theta[at + kLinkParameterCount + fc] *= 1.0 + u(rng);
  }
  if (r == 0) theta[3 * layout.perLink() + kLinkParameterCount + fc] *= 1.5;
  if (r == 1) {  // 1 kg at c = (0, 0, 0.15) in link 7's frame: about the frame's origin
    const int at = 6 * layout.perLink();
    const double mass = 1.0, c = 0.15, ic = 1e-3;
    theta[at + 0] += mass;
    theta[at + 3] += mass * c;           // m cz
    theta[at + 4] += ic + mass * c * c;  // Ixx
    theta[at + 7] += ic + mass * c * c;  // Iyy
    theta[at + 9] += ic;                 // Izz
  }
  m.setStandardParameters(theta);
  return m;
}

Summary summarize(const Model& nominal, const Trajectory& log) {
  SummarizeRequest s;
  s.model = nominal;
  s.robot_spec = "panda";
  s.data = &log;
  return std::move(summarizeRun(s).summaries.front());
}

double torqueError(const Eigen::MatrixXd& wtw, const Eigen::VectorXd& est,
                   const Eigen::VectorXd& truth) {
  const Eigen::VectorXd e = est - truth;
  return std::sqrt(e.dot(wtw * e) / truth.dot(wtw * truth));
}

void BM_FleetAcceptance(benchmark::State& state, bool stribeck) {
  const int seeds =
      std::getenv("DYNID_FLEET_SEEDS") ? std::atoi(std::getenv("DYNID_FLEET_SEEDS")) : 20;
  const Model nominal = nominalPanda();
  const BaseParameters base = structuralBaseParameters(nominal, StructuralOptions{});
  // The reference motion's W^T W: a nominal 60 s log's (its torques play no part).
  LeastSquaresStream reference(base, nominal);
  reference.addTrajectory(nominal, test::fleetLog(nominal, 60.0, 999, kRate));
  const Eigen::MatrixXd r = reference.augmentedFactor();
  const Eigen::Index b = base.numBase();
  const Eigen::MatrixXd wtw = (r.transpose() * r).topLeftCorner(b, b);
  int both = 0, false_flag = 0, seeds_run = 0;
  std::vector<double> gains;
  for (auto _ : state) {
    for (int seed = 1; seed <= seeds; ++seed) {
      std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
      std::vector<Summary> summaries;
      std::vector<Eigen::VectorXd> truths;
      for (int robot = 0; robot < kRobots; ++robot) {
        const Model truth = fleetRobot(nominal, robot, rng);
        Eigen::VectorXd fs(truth.numJoints());
        const int per = truth.parameterLayout().perLink();
        const int fc =
            kLinkParameterCount + truth.driveTerms().column(static_cast<int>(DriveTerm::kCoulomb));
        for (int j = 0; j < truth.numJoints(); ++j)
          fs[j] = 0.5 * truth.standardParameters()[j * per + fc];
        truths.push_back(base.project(truth.standardParameters()));
        const bool short_one = robot >= kShortFirst && robot <= kShortLast;
        std::vector<Summary> logs;
        for (int l = 0; l < (short_one ? 1 : 10); ++l)
          logs.push_back(summarize(
              nominal, test::fleetLog(truth, short_one ? 10.0 : 60.0,
                                      static_cast<std::uint64_t>(seed * 100000 + robot * 100 + l),
                                      kRate, 0.1, 1e-3, stribeck ? &fs : nullptr)));
        std::vector<const Summary*> all;
        for (const Summary& s : logs) all.push_back(&s);
        summaries.push_back(mergeSummaries(all, {}));
      }
      FleetRequest request;
      request.model = nominal;
      request.robot_spec = "panda";
      for (int robot = 0; robot < kRobots; ++robot) {
        FleetRobotInput in;
        in.name = "robot_" + std::to_string(robot);
        in.summary = &summaries[static_cast<std::size_t>(robot)];
        request.robots.push_back(in);
      }
      const FleetOutcome o = fleetRun(request);
      bool others = false;
      for (int robot = 2; robot < kRobots; ++robot)
        others = others || o.robots[static_cast<std::size_t>(robot)].verdict.outside;
      const bool odd = o.robots[0].verdict.outside && o.robots[1].verdict.outside;
      both += odd && !others ? 1 : 0;
      false_flag += others ? 1 : 0;
      for (int robot = kShortFirst; robot <= kShortLast; ++robot) {
        const FleetRobot& fr = o.robots[static_cast<std::size_t>(robot)];
        const Eigen::VectorXd& truth = truths[static_cast<std::size_t>(robot)];
        gains.push_back(torqueError(wtw, fr.alone.beta, truth) /
                        torqueError(wtw, fr.verdict.posterior, truth));
      }
      ++seeds_run;
      std::printf(
          "seed %d: odd flagged %d %d (z %.1f, %.1f), others flagged %d, spread rounds %d; "
          "verdict: %s\n",
          seed, o.robots[0].verdict.outside, o.robots[1].verdict.outside,
          o.robots[0].verdict.z.cwiseAbs().maxCoeff(), o.robots[1].verdict.z.cwiseAbs().maxCoeff(),
          others, o.prior.rounds, o.verdict.c_str());
      std::fflush(stdout);
    }
  }
  std::sort(gains.begin(), gains.end());
  state.counters["seeds"] = seeds_run;
  state.counters["both_and_only_pct"] = 100.0 * both / seeds_run;
  state.counters["false_flag_pct"] = 100.0 * false_flag / seeds_run;
  state.counters["short_gain_median"] = gains[gains.size() / 2];
  state.counters["short_gain_min"] = gains.front();
}
BENCHMARK_CAPTURE(BM_FleetAcceptance, model_as_identified, false)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_FleetAcceptance, stribeck, true)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace dynid

BENCHMARK_MAIN();
