#include "analysis/prepare.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

#include "core/errors.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"

namespace dynid {
namespace {

constexpr double kPi = std::numbers::pi;

// Two joints: q_j = A_j sin(w_j t) [deg in the file], tau_j = 3 q_j + 0.5 ddq_j [N m] plus noise.
double q(int j, double t) { return (j == 0 ? 0.8 : -0.5) * std::sin((j == 0 ? 1.1 : 2.3) * t); }
double dq(int j, double t) {
  const double w = j == 0 ? 1.1 : 2.3;
  return (j == 0 ? 0.8 : -0.5) * w * std::cos(w * t);
}
double ddq(int j, double t) {
  const double w = j == 0 ? 1.1 : 2.3;
  return -w * w * q(j, t);
}

/// A table log in ms and degrees, 1 kHz with jitter, a 50 ms gap at 3 s, one repeated stamp and
/// one pair of stamps out of order.
std::string writeLog(double noise) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-0.3e-3, 0.3e-3);
  std::normal_distribution<double> gauss(0.0, noise);
  std::vector<double> stamps;
  for (double t = 0.0; t < 6.0; t += 1e-3)
    if (t < 3.0 || t > 3.05) stamps.push_back(t + (t > 0.0 ? jitter(rng) : 0.0));
  stamps.insert(stamps.begin() + 100, stamps[100]);  // repeated
  std::swap(stamps[200], stamps[201]);               // out of order
  std::ostringstream out;
  out << "time_ms,q_a,q_b,tau_a,tau_b\n";
  out.precision(17);
  for (double t : stamps) {
    out << t * 1e3;
    for (int j = 0; j < 2; ++j) out << "," << q(j, t) * 180.0 / kPi;
    for (int j = 0; j < 2; ++j) out << "," << 3.0 * q(j, t) + 0.5 * ddq(j, t) + gauss(rng);
    out << "\n";
  }
  const std::string path = test::tempPath("log.csv");
  writeFileAtomically(path, out.str());
  return path;
}

LogSource tableSource(const std::string& path) {
  LogSource s;
  s.table = path;
  s.time_column = "time_ms";
  s.q_columns = "q_*";
  s.tau_columns = "tau_a,tau_b";
  return s;
}

PrepareOptions msAndDegrees() {
  PrepareOptions o;
  o.time_scale = 1e-3;
  o.angle_scale = kPi / 180.0;
  return o;
}

TEST(Prepare, CleansSplitsFiltersAndDifferentiatesARawLog) {
  const PrepareOutcome o = prepareLog(tableSource(writeLog(0.05)), msAndDegrees());
  EXPECT_EQ(o.repeated_stamps, 1);
  EXPECT_EQ(o.unsorted_stamps, 1);
  ASSERT_EQ(o.gaps.size(), 1u);  // the 50 ms gap, not the 1.6 ms jitter
  EXPECT_NEAR(o.gaps[0].first, 3.0, 2e-3);
  ASSERT_EQ(o.runs.size(), 2u);
  EXPECT_NEAR(o.rate, 1000.0, 1.0);  // the median step
  EXPECT_TRUE(o.dq_derived);
  const Trajectory& d = o.train;
  ASSERT_EQ(d.numJoints(), 2);
  // 0.2 s trimmed at each run's ends (2 / 10 Hz).
  EXPECT_NEAR(d.time[0], 0.2, 2e-3);
  double worst_q = 0, worst_dq = 0, worst_ddq = 0, worst_tau = 0;
  for (int k = 0; k < d.numSamples(); ++k) {
    const double t = d.time[k];
    for (int j = 0; j < 2; ++j) {
      worst_q = std::max(worst_q, std::abs(d.q(j, k) - q(j, t)));
      worst_dq = std::max(worst_dq, std::abs(d.dq(j, k) - dq(j, t)));
      worst_ddq = std::max(worst_ddq, std::abs(d.ddq(j, k) - ddq(j, t)));
      worst_tau = std::max(worst_tau, std::abs(d.tau(j, k) - (3.0 * q(j, t) + 0.5 * ddq(j, t))));
    }
  }
  // Motion at 0.2-0.4 Hz through a 10 Hz filter: the linear interpolation of jittered stamps and
  // the filter's residual gain leave ~1e-6 rad on q; each difference costs about a factor 10-100.
  EXPECT_LT(worst_q, 1e-5);
  EXPECT_LT(worst_dq, 1e-3);
  EXPECT_LT(worst_ddq, 2e-2);
  // 0.05 N m white noise at 1 kHz through 10 Hz (forward-backward): about 0.05 sqrt(2 x 10 / 500)
  // = 0.01 N m RMS left, under 0.05 at worst.
  EXPECT_LT(worst_tau, 0.05);
  // The noise estimate: the resampled minus the filtered torque, about the 0.05 N m put in.
  EXPECT_NEAR(o.tau_noise[0], 0.05, 0.01);
}

TEST(Prepare, ValidationFractionDecimationAndLoggedDq) {
  PrepareOptions o = msAndDegrees();
  o.validate_fraction = 0.25;
  o.decimate = 4;
  const PrepareOutcome out = prepareLog(tableSource(writeLog(0.0)), o);
  const int total = out.train.numSamples() + out.validate.numSamples();
  EXPECT_NEAR(out.validate.numSamples(), 0.25 * total, 3.0);  // the last quarter of each run
  EXPECT_NEAR(out.train.time[1] - out.train.time[0], 4.0 / out.rate, 1e-12);
  for (int k = 1; k < out.train.numSamples(); ++k)
    EXPECT_GT(out.train.time[k], out.train.time[k - 1]);  // strictly increasing across runs
}

TEST(Prepare, TheDefaultCutoffFitsSlowLogs) {
  // A 30 Hz log: 10 Hz would be too close to its 15 Hz Nyquist frequency; the default takes a
  // quarter of the rate.
  std::ostringstream text;
  text.precision(17);
  for (int k = 0; k < 900; ++k) text << k / 30.0 << " " << std::sin(k / 30.0) << " 0.5\n";
  const std::string path = test::tempPath("slow.txt");
  writeFileAtomically(path, text.str());
  // The table, its time, q, dq (none) and tau columns; no per-signal files; joints from q.
  const LogSource s{path, "1", "2", "", "3", "", "", "", "", 0};
  const PrepareOutcome o = prepareLog(s, PrepareOptions{});
  EXPECT_NEAR(o.rate, 30.0, 1e-9);
  EXPECT_NEAR(o.cutoff, 7.5, 1e-9);
  EXPECT_NEAR(prepareLog(tableSource(writeLog(0.0)), msAndDegrees()).cutoff, 10.0, 1e-12);
}

TEST(Prepare, RefusesWhatItCannotDo) {
  const std::string log = writeLog(0.0);
  PrepareOptions above_nyquist = msAndDegrees();
  above_nyquist.cutoff = 600.0;
  EXPECT_THROW(prepareLog(tableSource(log), above_nyquist), InputError);
  PrepareOptions long_trim = msAndDegrees();
  long_trim.trim = 5.0;  // longer than either run
  EXPECT_THROW(prepareLog(tableSource(log), long_trim), InputError);
  LogSource wrong = tableSource(log);
  wrong.tau_columns = "tau_a";  // one torque for two joints
  EXPECT_THROW(prepareLog(wrong, msAndDegrees()), ParseError);
  LogSource files;
  files.q_file = log;
  EXPECT_THROW(prepareLog(files, msAndDegrees()), InputError);  // no joint count, no time file
}

}  // namespace
}  // namespace dynid
