#include "analysis/studies/audit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "analysis/estimation/covariance.hpp"
#include "core/errors.hpp"
#include "data/puma560.hpp"
#include "identifiability/base_parameters.hpp"
#include "identifiability/least_squares_stream.hpp"
#include "tests/common/identification.hpp"

namespace dynid {
namespace {

/// A table of parameters x sessions.
AuditOutcome table(const std::vector<std::vector<double>>& estimates,
                   const std::vector<std::vector<double>>& sigmas,
                   const std::vector<std::string>& names) {
  AuditOutcome o;
  for (std::size_t i = 0; i < estimates.front().size(); ++i)
    o.sessions.push_back("s" + std::to_string(i + 1));
  for (std::size_t p = 0; p < names.size(); ++p) {
    AuditParameter a;
    a.name = names[p];
    a.group = names[p].rfind("F", 0) == 0 ? "friction" : "inertial";
    a.estimate = Eigen::Map<const Eigen::VectorXd>(estimates[p].data(),
                                                   static_cast<Eigen::Index>(estimates[p].size()));
    a.std_dev = Eigen::Map<const Eigen::VectorXd>(sigmas[p].data(),
                                                  static_cast<Eigen::Index>(sigmas[p].size()));
    o.parameters.push_back(a);
  }
  auditTest(o);
  return o;
}

TEST(AuditTest, TheRulesOnConstructedTables) {
  // Agreement: every estimate within a sigma of the others.
  AuditOutcome agree = table({{1.0, 1.1, 0.9}, {5.0, 5.05, 4.95}},
                             {{0.1, 0.1, 0.1}, {0.1, 0.1, 0.1}}, {"m1", "Fv2"});
  EXPECT_EQ(agree.verdict, "consistent");
  EXPECT_EQ(agree.flagged, 0);
  // chi2 of {1, 1.1, 0.9} about 1 with sigma 0.1: 0 + 1 + 1 = 2 on 2 dof: p = exp(-1).
  EXPECT_NEAR(agree.parameters[0].chi2, 2.0, 1e-12);
  EXPECT_NEAR(agree.parameters[0].p_value, std::exp(-1.0), 1e-12);
  // A friction term moved by 10 sigma in session 3: flagged, farthest there, drift in friction.
  AuditOutcome friction =
      table({{1.0, 1.1, 0.9}, {5.0, 5.0, 6.0}}, {{0.1, 0.1, 0.1}, {0.1, 0.1, 0.1}}, {"m1", "Fc2"});
  EXPECT_EQ(friction.flagged, 1);
  EXPECT_EQ(friction.flagged_friction, 1);
  EXPECT_EQ(friction.parameters[1].farthest, 2);
  EXPECT_EQ(friction.verdict, "drift in friction (Fc2)");
  EXPECT_EQ(friction.session_chi2.maxCoeff(), friction.session_chi2[2]);
  // Both groups.
  AuditOutcome both = table({{1.0, 2.0}, {5.0, 6.0}}, {{0.1, 0.1}, {0.1, 0.1}}, {"Izz1R", "Fv2"});
  EXPECT_EQ(both.verdict, "drift in inertial parameters (Izz1R) and drift in friction (Fv2)");
  // The same estimate with a larger sigma in one session weighs less in the mean.
  AuditOutcome weighted = table({{1.0, 2.0}}, {{0.1, 1.0}}, {"m1"});
  EXPECT_NEAR(weighted.parameters[0].mean, (1.0 / 0.01 + 2.0) / (1.0 / 0.01 + 1.0), 1e-12);
  // A zero sigma (an unexcited column in one session) carries no test.
  AuditOutcome unexcited = table({{1.0, 3.0}}, {{0.0, 0.1}}, {"m1"});
  EXPECT_EQ(unexcited.parameters[0].dof, 0);
  EXPECT_FALSE(unexcited.parameters[0].flagged);
  EXPECT_EQ(unexcited.verdict, "consistent");
}

/// The audit of base-parameter estimates, one per session, named s0, s1, ...
AuditOutcome auditOf(const BaseParameters& base, const std::vector<BaseEstimate>& estimates) {
  AuditOutcome o;
  const int count = static_cast<int>(estimates.size());
  for (int s = 0; s < count; ++s) o.sessions.push_back("s" + std::to_string(s));
  for (int j = 0; j < base.numBase(); ++j) {
    AuditParameter p;
    p.name = base.baseName(j);
    p.group = p.name.rfind("F", 0) == 0 ? "friction" : "inertial";
    p.estimate.resize(count);
    p.std_dev.resize(count);
    for (int s = 0; s < count; ++s) {
      p.estimate[s] = estimates[static_cast<std::size_t>(s)].beta[j];
      p.std_dev[s] = estimates[static_cast<std::size_t>(s)].std_dev[j];
    }
    o.parameters.push_back(p);
  }
  auditTest(o);
  return o;
}

/// Base-parameter estimates of `sessions` simulated logs of the PUMA with its drives (rotor
/// inertia, published friction; the same motion, independent torque noise), session `changed`
/// with Fc3 scaled by `scale`.
AuditOutcome sessions(int count, std::uint64_t seed, int changed, double scale) {
  const Model puma = makePuma560(true);
  const Eigen::VectorXd theta = puma.standardParameters();
  const ParameterLayout layout = puma.parameterLayout();
  const BaseParameters base = structuralBaseParameters(puma);
  std::vector<BaseEstimate> estimates;
  for (int s = 0; s < count; ++s) {
    Model truth = puma;
    if (s == changed) {
      Eigen::VectorXd t = theta;
      t[layout.driveIndex(2, DriveTerm::kCoulomb)] *= scale;
      truth.setStandardParameters(t);
    }
    LeastSquaresStream stream(base, truth);
    stream.addTrajectory(truth, test::pumaTrajectory(truth, 10.0, 0.5, seed * 100 + s));
    estimates.push_back(stream.estimate(LeastSquaresMethod::kOrdinary));
  }
  return auditOf(base, estimates);
}

// Sessions without change: about 5 % of the parameters flagged at the 5 % level; a 10 % change of
// one Coulomb coefficient in one session: flagged in (nearly) every seed. The suite runs 20 seeds;
// DYNID_AUDIT_SEEDS=N runs N to measure the rates (docs/MONITOR.md: 300 seeds).
TEST(AuditTest, FlagsAChangedFrictionTermAndLittleElse) {
  const char* env = std::getenv("DYNID_AUDIT_SEEDS");
  const int seeds = env ? std::max(1, std::atoi(env)) : 20;
  int flagged = 0, tested = 0, found = 0;
  for (std::uint64_t seed = 1; seed <= static_cast<std::uint64_t>(seeds); ++seed) {
    const AuditOutcome same = sessions(3, seed, -1, 1.0);
    flagged += same.flagged;
    tested += static_cast<int>(same.parameters.size());
    const AuditOutcome changed = sessions(3, seed, 1, 1.1);
    for (const AuditParameter& p : changed.parameters)
      if (p.name == "Fc3" && p.flagged && p.farthest == 1) ++found;
  }
  std::printf(
      "%d seeds: %d of %d parameters flagged without change (%.2f %%); the changed Fc3 "
      "found in %d\n",
      seeds, flagged, tested, 100.0 * flagged / tested, found);
  RecordProperty("flagged_without_change", flagged);
  RecordProperty("tested", tested);
  RecordProperty("changed_friction_found", found);
  // 20 seeds x 58 tests at 5 %: 58 expected, binomial sd 7.4; 6.5 % is 2 sd above (300 seeds
  // measure 4.7 %).
  EXPECT_LE(flagged, 0.065 * tested) << flagged << " of " << tested;
  EXPECT_GE(found, seeds - seeds / 20);
}

/// Sessions as real logs have them: the torque noise low-pass filtered (AR(1), rho 0.9: residuals
/// correlated over about 30 samples, as a filtered log's) and an unmodelled cogging torque
/// 0.3 sin(6 q_j) N m (model error, the same in every session), each session's covariance by
/// `policy`; session `changed` with Fc3 scaled by `scale`. Also counts, over the base parameters
/// of the sessions without model error, how many 95 % intervals cover the truth.
struct RealisticSessions {
  AuditOutcome outcome;
  int covered = 0, intervals = 0;
};
RealisticSessions realisticSessions(int count, std::uint64_t seed, int changed, double scale,
                                    CovariancePolicy policy, double cogging = 0.3) {
  const Model puma = makePuma560(true);
  const Eigen::VectorXd theta = puma.standardParameters();
  const ParameterLayout layout = puma.parameterLayout();
  const BaseParameters base = structuralBaseParameters(puma);
  RealisticSessions out;
  std::vector<BaseEstimate> estimates;
  for (int s = 0; s < count; ++s) {
    Model truth = puma;
    Eigen::VectorXd t = theta;
    if (s == changed) t[layout.driveIndex(2, DriveTerm::kCoulomb)] *= scale;
    truth.setStandardParameters(t);
    Trajectory data = test::pumaTrajectory(truth, 10.0, 0.0, seed * 100 + s);
    std::mt19937_64 rng(seed * 1000 + static_cast<std::uint64_t>(s));
    std::normal_distribution<double> normal(0.0, 0.5 * std::sqrt(1.0 - 0.81));  // sd 0.5 N m
    Eigen::VectorXd filtered = Eigen::VectorXd::Zero(6);
    for (int k = 0; k < data.numSamples(); ++k) {
      for (int j = 0; j < 6; ++j) filtered[j] = 0.9 * filtered[j] + normal(rng);
      data.tau.col(k) += filtered + cogging * (6.0 * data.q.col(k).array()).sin().matrix();
    }
    LeastSquaresStream stream(base, truth);
    stream.addTrajectory(truth, data);
    BaseEstimate e = stream.estimate(LeastSquaresMethod::kOrdinary);
    if (policy == CovariancePolicy::kHac)
      applyHacCovariance(
          truth, base, [&](const std::function<void(const Trajectory&)>& each) { each(data); },
          nullptr, scoreWeights(e, false), e);
    if (s != changed) {
      const Eigen::VectorXd beta = base.project(t);
      for (int j = 0; j < base.numBase(); ++j, ++out.intervals)
        out.covered += std::abs(e.beta[j] - beta[j]) <= 1.959964 * e.std_dev[j];
    }
    estimates.push_back(std::move(e));
  }
  out.outcome = auditOf(base, estimates);
  return out;
}

// Filtered residuals and a small model error: the white covariance flags most parameters of
// sessions that did not change (and the audit then calls its sigma too small); hac flags at most
// about 5 % and still finds a 10 % change of Fc3; its intervals cover the truth about 95 % of the
// time (without the cogging, which biases the estimate whatever the covariance).
// DYNID_AUDIT_SEEDS=N runs N seeds (docs/IDENTIFIABILITY.md: the rates).
TEST(AuditTest, HacHoldsOnFilteredResidualsAndModelError) {
  const char* env = std::getenv("DYNID_AUDIT_SEEDS");
  const int seeds = env ? std::max(1, std::atoi(env)) : 10;
  int flagged = 0, flagged_white = 0, tested = 0, found = 0, covered = 0, intervals = 0;
  int too_small_white = 0;
  for (std::uint64_t seed = 1; seed <= static_cast<std::uint64_t>(seeds); ++seed) {
    const AuditOutcome same = realisticSessions(3, seed, -1, 1.0, CovariancePolicy::kHac).outcome;
    flagged += same.flagged;
    tested += static_cast<int>(same.parameters.size());
    const AuditOutcome white =
        realisticSessions(3, seed, -1, 1.0, CovariancePolicy::kWhite).outcome;
    for (const AuditParameter& p : white.parameters) flagged_white += p.p_value < white.level;
    too_small_white += white.sigma_too_small;
    const AuditOutcome changed = realisticSessions(3, seed, 1, 1.1, CovariancePolicy::kHac).outcome;
    for (const AuditParameter& p : changed.parameters)
      if (p.name == "Fc3" && p.flagged && p.farthest == 1) ++found;
    const RealisticSessions clean =
        realisticSessions(2, seed + 1000, -1, 1.0, CovariancePolicy::kHac, 0.0);
    covered += clean.covered;
    intervals += clean.intervals;
  }
  std::printf(
      "%d seeds: hac flags %d of %d parameters without change (%.2f %%), white sigma %d "
      "(%.2f %%; the audit finds them too small in %d of the audits); the changed Fc3 found in "
      "%d; coverage %.2f %%\n",
      seeds, flagged, tested, 100.0 * flagged / tested, flagged_white,
      100.0 * flagged_white / tested, too_small_white, found, 100.0 * covered / intervals);
  RecordProperty("flagged_without_change", flagged);
  RecordProperty("flagged_white", flagged_white);
  RecordProperty("changed_friction_found", found);
  RecordProperty("coverage", std::to_string(static_cast<double>(covered) / intervals));
  // 10 seeds x 58 tests at 5 %: 29 expected, binomial sd 5.2: 7.5 % is 2.7 sd above.
  EXPECT_LE(flagged, 0.075 * tested) << flagged << " of " << tested;
  EXPECT_GT(flagged_white, tested / 2) << flagged_white << " of " << tested;
  EXPECT_EQ(too_small_white, seeds);
  EXPECT_GE(found, seeds - seeds / 10);
  // 10 seeds x 2 sessions x 58 intervals = 1160: binomial sd 0.64 %; 92-98 % leaves the
  // batch-means variance's own error (about 150 batches per session) a point of room.
  EXPECT_GE(covered, 0.92 * intervals) << covered << " of " << intervals;
  EXPECT_LE(covered, 0.98 * intervals) << covered << " of " << intervals;
}

/// The dispersion rule on constructed tables: every parameter 3 sigma apart alike is "sigma too
/// small"; one parameter far beyond the rest is drift on top of it.
TEST(AuditTest, SeparatesSigmaTooSmallFromDrift) {
  std::vector<std::vector<double>> estimates, sigmas;
  std::vector<std::string> names;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 3.0);  // spread 3 sigma: dispersion about 9
  for (int p = 0; p < 30; ++p) {
    estimates.push_back({normal(rng), normal(rng), normal(rng)});
    sigmas.push_back({1.0, 1.0, 1.0});
    names.push_back((p % 3 == 0 ? "Fv" : "m") + std::to_string(p));
  }
  AuditOutcome alike = table(estimates, sigmas, names);
  EXPECT_TRUE(alike.sigma_too_small);
  EXPECT_GT(alike.sigma_scale, 2.0);
  EXPECT_LT(alike.sigma_scale, 4.5);
  EXPECT_EQ(alike.verdict.rfind("the sigma are too small", 0), 0u) << alike.verdict;
  // One parameter 60 sigma off in session 2: drift beyond the common dispersion.
  estimates[4][1] += 60.0;
  AuditOutcome drift = table(estimates, sigmas, names);
  EXPECT_TRUE(drift.sigma_too_small);
  EXPECT_TRUE(drift.parameters[4].flagged);
  EXPECT_EQ(drift.parameters[4].farthest, 1);
  const std::size_t beyond = drift.verdict.find("beyond that, drift in inertial parameters (");
  ASSERT_NE(beyond, std::string::npos) << drift.verdict;
  EXPECT_NE(drift.verdict.find("m4", beyond), std::string::npos) << drift.verdict;
  // Sessions that agree within their sigma: no dispersion.
  for (auto& row : estimates) row = {normal(rng) / 3.0, normal(rng) / 3.0, normal(rng) / 3.0};
  AuditOutcome agree = table(estimates, sigmas, names);
  EXPECT_FALSE(agree.sigma_too_small);
  EXPECT_EQ(agree.sigma_scale, 1.0);
}

TEST(AuditRun, RefusesBadRequests) {
  AuditRequest r;
  EXPECT_THROW(auditRun(r), InputError);
  r.estimate_files = {"a.json"};
  EXPECT_THROW(auditRun(r), InputError);  // one session
  r.data_files = {"a.csv", "b.csv"};
  EXPECT_THROW(auditRun(r), InputError);  // both kinds
}

}  // namespace
}  // namespace dynid
