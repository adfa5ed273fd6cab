#include "analysis/logs/prepare.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <numbers>
#include <random>
#include <sstream>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/io.hpp"
#include "tests/common/sample_models.hpp"
#include "tests/common/scratch_dataset.hpp"

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
  s.tables = {path};
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
  const LogSource s{{path}, "1", "2", "", "3", "", "", "", "", 0, false, "", ""};
  const PrepareOutcome o = prepareLog(s, PrepareOptions{});
  EXPECT_NEAR(o.rate, 30.0, 1e-9);
  EXPECT_NEAR(o.cutoff, 7.5, 1e-9);
  EXPECT_NEAR(prepareLog(tableSource(writeLog(0.0)), msAndDegrees()).cutoff, 10.0, 1e-12);
}

/// A clean 1 kHz table in seconds and radians over [t0, t1): time, q1, q2, then the torque divided
/// by `divide` per joint (a motor current when `divide` holds torque constant x gear ratio).
/// `stall` repeats the sample at 2.5 s that many times with advancing stamps (a stalled logger);
/// `rest` holds the signals bit-identical from 1 s to 3 s (the robot at rest).
std::string writeCleanLog(const std::string& name, double t0, double t1, Eigen::Vector2d divide,
                          int stall = 0, bool rest = false) {
  std::ostringstream out;
  out.precision(17);
  out << "t,q1,q2,c1,c2\n";
  int held = 0;
  double frozen = -1.0;
  for (int k = 0; t0 + k * 1e-3 < t1; ++k) {
    const double stamp = t0 + k * 1e-3;
    double t = stamp;
    if (rest && stamp >= 1.0 && stamp < 3.0) t = 1.0;
    if (stall > 0 && std::abs(stamp - 2.5) < 1e-9) frozen = t;
    if (frozen >= 0.0 && held < stall && stamp > 2.5) {
      t = frozen;
      ++held;
    }
    out << stamp;
    for (int j = 0; j < 2; ++j) out << "," << q(j, t);
    for (int j = 0; j < 2; ++j) out << "," << (3.0 * q(j, t) + 0.5 * ddq(j, t)) / divide[j];
    out << "\n";
  }
  const std::string path = test::tempPath(name);
  writeFileAtomically(path, out.str());
  return path;
}

LogSource cleanSource(std::vector<std::string> tables) {
  LogSource s;
  s.tables = std::move(tables);
  s.time_column = "t";
  s.q_columns = "q*";
  s.tau_columns = "c*";
  return s;
}

TEST(Prepare, CurrentsBecomeTorquesThroughTorqueConstantsAndGearRatios) {
  const Eigen::Vector2d kt(0.2, 0.05), gear(100.0, 50.0);
  const PrepareOutcome torques =
      prepareLog(cleanSource({writeCleanLog("tau.csv", 0, 4, Eigen::Vector2d::Ones())}), {});
  LogSource currents = cleanSource({writeCleanLog("amps.csv", 0, 4, kt.cwiseProduct(gear))});
  currents.current = true;
  PrepareOptions o;
  o.torque_constants = kt;
  o.gear_ratios = gear;
  const PrepareOutcome converted = prepareLog(currents, o);
  ASSERT_EQ(converted.train.numSamples(), torques.train.numSamples());
  // current x kt x G reproduces the torque up to the round-off of the division in the file.
  EXPECT_LT((converted.train.tau - torques.train.tau).cwiseAbs().maxCoeff(), 1e-12);
  // Currents without torque constants, with the wrong count, or a zero constant are refused;
  // constants without currents too.
  PrepareOptions missing;
  EXPECT_THROW(prepareLog(currents, missing), InputError);
  PrepareOptions short_list;
  short_list.torque_constants = Eigen::VectorXd::Constant(1, 0.2);
  EXPECT_THROW(prepareLog(currents, short_list), InputError);
  PrepareOptions zero = o;
  zero.gear_ratios[1] = 0.0;
  EXPECT_THROW(prepareLog(currents, zero), InputError);
  EXPECT_THROW(prepareLog(cleanSource({writeCleanLog("t2.csv", 0, 4, Eigen::Vector2d::Ones())}), o),
               InputError);
}

TEST(Prepare, SkippedDropoutsGiveTheLogWithoutThoseRowsAndLinesStayTheFiles) {
  // 2 s at 1 kHz; data row 100 (line 102) has a nan: skipped, the outcome is the file without
  // that line; with a stamp set back 1 s at line 1502 too, the error names line 1502.
  const auto text = [](bool dropout, bool back) {
    std::ostringstream out;
    out.precision(17);
    out << "t,q1,q2,tau1,tau2\n";
    for (int k = 0; k < 2000; ++k) {
      if (k == 100 && !dropout) continue;
      const double t = k == 1500 && back ? k * 1e-3 - 1.0 : k * 1e-3;
      out << t << ',' << (k == 100 ? std::string("nan") : std::to_string(std::sin(t))) << ','
          << std::cos(2.0 * t) << ',' << 3.0 * std::sin(t + 0.2) << ',' << std::cos(t) << '\n';
    }
    return out.str();
  };
  LogSource source;
  source.time_column = "t";
  source.q_columns = "q*";
  source.tau_columns = "tau*";
  source.tables = {test::writeTemp("without_dropout.csv", text(false, false))};
  const PrepareOutcome without = prepareLog(source, {});
  source.tables = {test::writeTemp("dropout.csv", text(true, false))};
  EXPECT_THROW(prepareLog(source, {}), ParseError);  // refused unless asked
  source.skip_missing = true;
  const PrepareOutcome skipped = prepareLog(source, {});
  EXPECT_EQ(skipped.skipped_missing, 1);
  EXPECT_EQ(skipped.raw_samples, without.raw_samples);
  EXPECT_EQ(skipped.train.q, without.train.q);
  EXPECT_EQ(skipped.train.tau, without.train.tau);
  bool warned = false;
  for (const std::string& w : skipped.warnings)
    warned = warned || w.find(
                           "1 row(s) with a missing value (empty, nan or inf) left out "
                           "(`skip_missing`), at line(s) 102") != std::string::npos;
  EXPECT_TRUE(warned);
  // Through scratch files (dynid prepare's path: the table's columns spilled as they are parsed):
  // the same row left out, the same numbers.
  const std::string dir = test::tempPath("dropout_scratch");
  std::filesystem::create_directories(dir);
  const PrepareOutcome spilled = prepareLog(source, {}, 0, dir);
  EXPECT_EQ(spilled.skipped_missing, 1);
  ASSERT_EQ(spilled.trainSamples(), skipped.train.numSamples());
  Trajectory rows;
  spilled.scratch_train->rows(0, skipped.train.numSamples(), rows);
  EXPECT_EQ(rows.q, skipped.train.q);
  EXPECT_EQ(rows.tau, skipped.train.tau);
  source.tables = {test::writeTemp("dropout_and_reset.csv", text(true, true))};
  for (const std::string& scratch : {std::string(), dir}) try {
      prepareLog(source, {}, 0, scratch);
      ADD_FAILURE() << "no error";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.line(), 1502) << e.what();  // the file's line, past the skipped one
    }
}

TEST(Prepare, StalledRepeatsAreDroppedAndRestIsKept) {
  const Eigen::Vector2d one = Eigen::Vector2d::Ones();
  // A 3-sample stall at 2.5 s: dropped and bridged; the result matches the clean log's.
  const PrepareOutcome clean = prepareLog(cleanSource({writeCleanLog("c.csv", 0, 5, one)}), {});
  const PrepareOutcome stalled =
      prepareLog(cleanSource({writeCleanLog("s.csv", 0, 5, one, 3)}), {});
  EXPECT_EQ(clean.stalled_repeats, 0);
  EXPECT_EQ(stalled.stalled_repeats, 3);
  ASSERT_EQ(stalled.runs.size(), 1u);
  ASSERT_EQ(stalled.train.numSamples(), clean.train.numSamples());
  // Linear interpolation over the 4 ms bridge of a < 0.5 Hz motion, then the 10 Hz filter.
  EXPECT_LT((stalled.train.q - clean.train.q).cwiseAbs().maxCoeff(), 1e-6);
  PrepareOptions keep;
  keep.keep_stalled = true;
  EXPECT_EQ(prepareLog(cleanSource({writeCleanLog("k.csv", 0, 5, one, 3)}), keep).stalled_repeats,
            0);
  // Two seconds bit-identical: the robot at rest, far longer than the gap limit: kept whole, no
  // gap, one run.
  const PrepareOutcome rest =
      prepareLog(cleanSource({writeCleanLog("r.csv", 0, 5, one, 0, true)}), {});
  EXPECT_EQ(rest.stalled_repeats, 0);
  EXPECT_TRUE(rest.gaps.empty());
  EXPECT_EQ(rest.runs.size(), 1u);
}

TEST(Prepare, SeveralFilesAreSeparateRunsNeverJoined) {
  const Eigen::Vector2d one = Eigen::Vector2d::Ones();
  // Two recordings whose clocks both start at 0 (and a third in absolute time, later on).
  const std::string a = writeCleanLog("a.csv", 0, 3, one), b = writeCleanLog("b.csv", 0, 2, one),
                    c = writeCleanLog("c.csv", 100, 102, one);
  const PrepareOutcome o = prepareLog(cleanSource({a, b, c}), {});
  ASSERT_EQ(o.runs.size(), 3u);
  EXPECT_EQ(o.runs[0].file, 0);
  EXPECT_EQ(o.runs[1].file, 1);
  EXPECT_EQ(o.runs[2].file, 2);
  EXPECT_EQ(o.runs[0].time_offset, 0.0);
  // b shifted to start 1 s after a ends; c already starts later and keeps its stamps.
  EXPECT_NEAR(o.runs[1].time_offset, 3.0 - 1e-3 + 1.0, 1e-9);
  EXPECT_EQ(o.runs[2].time_offset, 0.0);
  EXPECT_TRUE(o.gaps.empty());  // file boundaries are not gaps
  EXPECT_EQ(o.raw_samples, 3000 + 2000 + 2000);
  for (int k = 1; k < o.train.numSamples(); ++k)
    ASSERT_GT(o.train.time[k], o.train.time[k - 1]) << k;
  // Each file's samples are its own: every output sample of b matches b's signals at its own
  // time (no derivative or filter across the boundary from a's end, where q differs).
  double worst = 0.0;
  for (int k = 0; k < o.train.numSamples(); ++k) {
    const double t = o.train.time[k];
    if (t < o.runs[1].start + o.runs[1].time_offset || t > 10.0) continue;
    const double local = t - o.runs[1].time_offset;
    for (int j = 0; j < 2; ++j)
      worst = std::max(worst, std::abs(o.train.ddq(j, k) - ddq(j, local)));
  }
  // Twice-differenced filtered q: the bound of the single-file test above.
  EXPECT_LT(worst, 2e-2);
  // A file whose q glob matches another joint count is refused, naming it.
  std::ostringstream three;
  three << "t,q1,q2,q3,c1,c2,c3\n";
  for (int k = 0; k < 2000; ++k) three << k * 1e-3 << ",0,0,0,0,0,0\n";
  const std::string wide = test::tempPath("wide.csv");
  writeFileAtomically(wide, three.str());
  try {
    prepareLog(cleanSource({a, wide}), {});
    ADD_FAILURE() << "a 3-joint file after a 2-joint one was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("wide.csv"), std::string::npos) << e.what();
  }
}

/// One joint at 1 kHz for 60 s: q = 0.5 sin(2 pi 0.2 t) + 0.3 sin(2 pi 0.5 t) rad plus white
/// noise of `noise` rad; tau = 2 q.
std::string writeSpectrumLog(const std::string& name, double noise) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> gauss(0.0, noise);
  std::ostringstream out;
  out.precision(17);
  for (int k = 0; k < 60000; ++k) {
    const double t = k * 1e-3;
    const double x = 0.5 * std::sin(2 * kPi * 0.2 * t) + 0.3 * std::sin(2 * kPi * 0.5 * t);
    out << t << " " << x + gauss(rng) << " " << 2.0 * x << "\n";
  }
  const std::string path = test::tempPath(name);
  writeFileAtomically(path, out.str());
  return path;
}

TEST(Prepare, AutoCutoffIsFiveTimesTheTrajectoryBandBelowTheNoise) {
  PrepareOptions o;
  o.auto_cutoff = true;
  // Quiet encoders: the band edge is the 0.5 Hz sine (bins of 1000 / 16384 Hz; Hann spreads a
  // line over +-2 bins), the cutoff five times it.
  const LogSource quiet{
      {writeSpectrumLog("quiet.txt", 1e-6)}, "1", "2", "", "3", "", "", "", "", 0, false, "", ""};
  const PrepareOutcome a = prepareLog(quiet, o);
  EXPECT_GT(a.trajectory_band, 0.45);
  EXPECT_LT(a.trajectory_band, 0.7);
  EXPECT_NEAR(a.cutoff, 5.0 * a.trajectory_band, 1e-12);
  EXPECT_GT(a.noise_edge, a.cutoff);
  EXPECT_NE(a.cutoff_reason.find("auto"), std::string::npos);
  // Noisy encoders (1e-3 rad white, a floor of 2e-9 rad^2/Hz): the spectrum meets the floor
  // below five times the band, and the cutoff stops there.
  const LogSource noisy{
      {writeSpectrumLog("noisy.txt", 1e-3)}, "1", "2", "", "3", "", "", "", "", 0, false, "", ""};
  const PrepareOutcome b = prepareLog(noisy, o);
  EXPECT_LT(b.noise_edge, 5.0 * b.trajectory_band);
  EXPECT_NEAR(b.cutoff, std::max(b.noise_edge, 1.5 * b.trajectory_band), 1e-12);
  // A cutoff that close to the band is said (friction's bias), five times the band is not.
  const auto warned = [](const PrepareOutcome& p) {
    for (const std::string& w : p.warnings)
      if (w.find("within five times q's trajectory band") != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(warned(b));
  EXPECT_FALSE(warned(a));
  PrepareOptions low;
  low.cutoff = 1.0;  // twice the 0.5 Hz sine
  EXPECT_TRUE(warned(prepareLog(quiet, low)));
  // The spectra are normalised: one joint's q integrates to 1 (without DC).
  const Spectrum& q = a.q_spectrum;
  EXPECT_NEAR(q.density.tail(q.density.size() - 1).sum(), 1.0, 1e-9);
  // The excerpt: 2 s of the raw and filtered torque.
  EXPECT_EQ(a.excerpt_time.size(), 2000);
  EXPECT_EQ(a.excerpt_raw.cols(), 1);
}

TEST(Prepare, SavitzkyGolayDerivativesMatchTheMotion) {
  PrepareOptions o = msAndDegrees();
  o.savitzky_golay = true;
  o.rate = 1000.0;
  o.cutoff = 8.0;
  const PrepareOutcome out = prepareLog(tableSource(writeLog(0.0)), o);
  EXPECT_EQ(out.savgol_window, 2 * 16 + 1);  // a quarter period of 8 Hz: 1000 / (8 x 8) = 15.6
  double worst_ddq = 0.0;
  for (int k = 0; k < out.train.numSamples(); ++k)
    for (int j = 0; j < 2; ++j)
      worst_ddq = std::max(worst_ddq, std::abs(out.train.ddq(j, k) - ddq(j, out.train.time[k])));
  // The central-difference bound of the first test: jittered stamps interpolated, then filtered.
  EXPECT_LT(worst_ddq, 2e-2);
  PrepareOptions even = o;
  even.savgol_window = 20;
  EXPECT_THROW(prepareLog(tableSource(writeLog(0.0)), even), InputError);
}

TEST(Prepare, HoldsOutWholeRunsAndTimeRanges) {
  const Eigen::Vector2d one = Eigen::Vector2d::Ones();
  const std::string a = writeCleanLog("ha.csv", 0, 3, one), b = writeCleanLog("hb.csv", 0, 2, one);
  // The second recording held out whole.
  PrepareOptions by_run;
  by_run.validate_runs = {1};
  const PrepareOutcome r = prepareLog(cleanSource({a, b}), by_run);
  ASSERT_EQ(r.runs.size(), 2u);
  EXPECT_EQ(r.train.numSamples(), r.runs[0].samples);
  EXPECT_EQ(r.validate.numSamples(), r.runs[1].samples);
  EXPECT_GE(r.validate.time[0], r.runs[1].start + r.runs[1].time_offset);
  // A time range inside the first recording, plus the last 10 % of each run.
  PrepareOptions by_time;
  by_time.validate_ranges = {{1.0, 1.5}};
  by_time.validate_fraction = 0.1;
  const PrepareOutcome t = prepareLog(cleanSource({a, b}), by_time);
  int in_range = 0;
  for (int k = 0; k < t.validate.numSamples(); ++k)
    if (t.validate.time[k] >= 1.0 && t.validate.time[k] <= 1.5) ++in_range;
  // 1.0 to 1.5 s at 1 kHz, both ends; an end stamp may fall past 1.5 by round-off.
  EXPECT_NEAR(in_range, 501, 1);
  for (int k = 0; k < t.train.numSamples(); ++k)
    EXPECT_FALSE(t.train.time[k] >= 1.0 && t.train.time[k] <= 1.5) << t.train.time[k];
  const int total = r.train.numSamples() + r.validate.numSamples();
  EXPECT_EQ(t.train.numSamples() + t.validate.numSamples(), total);  // every sample once
  // A run that does not exist, or everything held out, is refused.
  PrepareOptions missing;
  missing.validate_runs = {2};
  EXPECT_THROW(prepareLog(cleanSource({a, b}), missing), InputError);
  PrepareOptions everything;
  everything.validate_runs = {0, 1};
  EXPECT_THROW(prepareLog(cleanSource({a, b}), everything), InputError);
}

TEST(Prepare, LoggedAccelerationsAreUsedUnlessAsked) {
  // A log whose ddq column is twice the true acceleration (a signal that differs from d2q/dt2):
  // used when logged, ignored with derive_ddq.
  std::ostringstream text;
  text.precision(17);
  text << "t,q1,tau1,a1\n";
  for (int k = 0; k < 5000; ++k) {
    const double t = k * 1e-3;
    text << t << "," << q(0, t) << "," << 3.0 * q(0, t) << "," << 2.0 * ddq(0, t) << "\n";
  }
  const std::string path = test::tempPath("accel.csv");
  writeFileAtomically(path, text.str());
  LogSource s;
  s.tables = {path};
  s.time_column = "t";
  s.q_columns = "q1";
  s.tau_columns = "tau1";
  s.ddq_columns = "a1";
  const PrepareOutcome logged = prepareLog(s, {});
  EXPECT_TRUE(logged.ddq_logged);
  PrepareOptions derive;
  derive.derive_ddq = true;
  const PrepareOutcome derived = prepareLog(s, derive);
  EXPECT_FALSE(derived.ddq_logged);
  for (int k = 0; k < logged.train.numSamples(); k += 500) {
    const double t = logged.train.time[k];
    // The filtered 1.1 rad/s motion: ~1e-6 on the logged signal, ~1e-4 on twice-differenced q.
    EXPECT_NEAR(logged.train.ddq(0, k), 2.0 * ddq(0, t), 1e-5) << t;
    EXPECT_NEAR(derived.train.ddq(0, k), ddq(0, t), 1e-3) << t;
  }
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

/// A log of `joints` sinusoids at 1 kHz (joint j: 0.3 + 0.05 j rad at 0.4 + 0.1 j Hz), at rest
/// for `rest` seconds before and after `seconds` of motion; columns q_<name(j)> and
/// tau_<name(j)> written in the joint order `order`, stamps as `stamp(t)` in the file's unit and
/// angles times `angle` (1: radians).
struct JointsLog {
  int joints = 2;
  std::vector<int> order;  // empty: 0, 1, ...
  std::function<std::string(int)> name = [](int j) { return std::to_string(j + 1); };
  std::function<std::string(double)> stamp = [](double t) { return formatNumber(t, 17); };
  double seconds = 4.0, rest = 0.0, step = 1e-3, angle = 1.0;
};
double motion(int j, double t, double seconds) {
  const double s = std::clamp(t, 0.0, seconds);
  return (0.3 + 0.05 * j) * std::sin(2.0 * kPi * (0.4 + 0.1 * j) * s) *
         std::sin(kPi * s / seconds);  // zero velocity at both ends of the motion
}
std::string writeJointsLog(const std::string& file, const JointsLog& log) {
  std::vector<int> order = log.order;
  if (order.empty())
    for (int j = 0; j < log.joints; ++j) order.push_back(j);
  std::ostringstream out;
  out.precision(17);
  out << "t";
  for (const char* kind : {"q_", "tau_"})
    for (int j : order) out << "," << kind << log.name(j);
  out << "\n";
  const auto samples = static_cast<long>(std::lround((log.seconds + 2.0 * log.rest) / log.step));
  for (long k = 0; k <= samples; ++k) {
    const double t = k * log.step;
    out << log.stamp(t);
    for (int j : order) out << "," << log.angle * motion(j, t - log.rest, log.seconds);
    for (int j : order) out << "," << 2.0 * (j + 1) * motion(j, t - log.rest, log.seconds);
    out << "\n";
  }
  const std::string path = test::tempPath(file);
  writeFileAtomically(path, out.str());
  return path;
}
LogSource jointsSource(const std::string& path) {
  LogSource s;
  s.tables = {path};
  s.time_column = "t";
  s.q_columns = "q_*";
  s.tau_columns = "tau_*";
  return s;
}
/// The largest difference between the prepared q and the motion, over joints and samples.
double qError(const Trajectory& d, double rest, double seconds) {
  double worst = 0.0;
  for (int k = 0; k < d.numSamples(); ++k)
    for (int j = 0; j < d.numJoints(); ++j)
      worst = std::max(worst, std::abs(d.q(j, k) - motion(j, d.time[k] - rest, seconds)));
  return worst;
}

// The torque can skip the filter (the raw measured torque papers validate against) or have its
// own cutoff; q is prepared alike either way, and the default trim follows the slowest filter.
TEST(Prepare, TorqueHasItsOwnCutoffWhenAsked) {
  const std::string log = writeLog(0.05);
  const auto tau_rms = [](const Trajectory& d) {
    double sum = 0.0;
    for (int k = 0; k < d.numSamples(); ++k)
      for (int j = 0; j < 2; ++j) {
        const double t = d.time[k];
        sum += std::pow(d.tau(j, k) - (3.0 * q(j, t) + 0.5 * ddq(j, t)), 2);
      }
    return std::sqrt(sum / (2.0 * d.numSamples()));
  };
  const PrepareOutcome filtered = prepareLog(tableSource(log), msAndDegrees());
  PrepareOptions none = msAndDegrees();
  none.tau_cutoff = 0.0;
  const PrepareOutcome raw = prepareLog(tableSource(log), none);
  EXPECT_EQ(raw.train.q, filtered.train.q);
  EXPECT_EQ(raw.tau_cutoff, 0.0);
  // 0.05 N m of white noise: all of it left unfiltered, about a fifth through 10 Hz.
  EXPECT_GT(tau_rms(raw.train), 0.04);
  EXPECT_LT(tau_rms(filtered.train), 0.02);
  PrepareOptions slow = msAndDegrees();
  slow.tau_cutoff = 4.0;
  const PrepareOutcome own = prepareLog(tableSource(log), slow);
  EXPECT_EQ(own.tau_cutoff, 4.0);
  EXPECT_EQ(own.trim, 0.5);  // 2 / 4 Hz, the slower filter's
  EXPECT_LT(tau_rms(own.train), tau_rms(filtered.train));
}

// Globs take the joints in the order of the numbers in the column names (q_joint2 before
// q_joint10), never the file's, and prepare records which column went to which joint. The file's
// order used to be taken: 96 % torque error on a real log, exit 0.
TEST(Prepare, GlobsTakeJointsInNaturalOrderAndTheColumnsAreRecorded) {
  JointsLog log;
  log.joints = 10;
  log.order = {9, 1, 0, 2, 3, 4, 5, 6, 8, 7};  // joint10, joint2, joint1, ...
  log.name = [](int j) { return "joint" + std::to_string(j + 1); };
  const PrepareOutcome o = prepareLog(jointsSource(writeJointsLog("natural.csv", log)), {});
  ASSERT_EQ(o.columns.size(), 1u);
  for (int j = 0; j < 10; ++j) {
    EXPECT_EQ(o.columns[0].q[j], "q_joint" + std::to_string(j + 1));
    EXPECT_EQ(o.columns[0].tau[j], "tau_joint" + std::to_string(j + 1));
  }
  // Sinusoids of 0.4-1.3 Hz through the default 10 Hz filter: ~1e-6 rad; a swapped joint: 0.1.
  EXPECT_LT(qError(o.train, 0.0, log.seconds), 1e-4);
  // Names one letter apart are ordered by that letter (q_a before q_b, whatever the file says).
  JointsLog lettered;
  lettered.order = {1, 0};
  lettered.name = [](int j) { return std::string(1, static_cast<char>('a' + j)); };
  const PrepareOutcome l = prepareLog(jointsSource(writeJointsLog("lettered.csv", lettered)), {});
  EXPECT_EQ(l.columns[0].q, (std::vector<std::string>{"q_a", "q_b"}));
  EXPECT_LT(qError(l.train, 0.0, lettered.seconds), 1e-4);
  // Names that carry no joint number (or the same ones) cannot be ordered: the list is asked for.
  JointsLog named = log;
  named.joints = 3;
  named.order = {};
  named.name = [](int j) { return std::vector<std::string>{"shoulder", "elbow", "wrist"}[j]; };
  try {
    prepareLog(jointsSource(writeJointsLog("named.csv", named)), {});
    ADD_FAILURE() << "an order that names cannot tell was taken";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("list the columns in joint order"), std::string::npos)
        << e.what();
  }
  named.name = [](int j) {
    return "arm2_" + std::vector<std::string>{"shoulder", "elbow", "wrist"}[j];
  };
  EXPECT_THROW(prepareLog(jointsSource(writeJointsLog("same.csv", named)), {}), ParseError);
}

/// The message of the InputError `f` throws ("" when it throws none).
template <class F>
std::string inputError(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A unit mistake gives motion no robot makes: refused with the likely cause and the option that
// fixes it, where it used to give a 22 % fit at condition number 1e8 without a word.
TEST(Prepare, UnitMistakesAreRefusedNamingTheOptionThatFixesThem) {
  JointsLog ms;
  ms.stamp = [](double t) { return formatNumber(t * 1e3, 17); };
  const std::string in_ms = writeJointsLog("unit_ms.csv", ms);
  // Milliseconds read as seconds: a 1 Hz log, too slow for dynamics.
  EXPECT_NE(inputError([&] { prepareLog(jointsSource(in_ms), {}); }).find("`time_unit` ms"),
            std::string::npos);
  PrepareOptions as_ms;
  as_ms.time_scale = 1e-3;
  EXPECT_NO_THROW(prepareLog(jointsSource(in_ms), as_ms));
  // Seconds read as milliseconds: a 1 MHz log.
  EXPECT_NE(inputError([&] {
              prepareLog(jointsSource(writeJointsLog("unit_s.csv", {})), as_ms);
            }).find("`time_unit`"),
            std::string::npos);
  // Degrees read as radians: 57 times the speed, past any robot's.
  JointsLog degrees;
  degrees.angle = 20.0 * 180.0 / kPi;  // 20 times the motion, in degrees: 1000 times read as rad
  const std::string message =
      inputError([&] { prepareLog(jointsSource(writeJointsLog("deg.csv", degrees)), {}); });
  EXPECT_NE(message.find("`angle_unit`"), std::string::npos) << message;
  EXPECT_NE(message.find("joint 1"), std::string::npos) << message;  // the first past the bound
  // A bound of the robot's: the motion itself (up to 1.3 rad/s) beyond 0.5 rad/s.
  PrepareOptions slow_robot;
  slow_robot.dq_bound = Eigen::VectorXd::Constant(1, 0.5);
  EXPECT_NE(inputError([&] {
              prepareLog(jointsSource(writeJointsLog("ok.csv", {})), slow_robot);
            }).find("`dq_max`"),
            std::string::npos);
  slow_robot.dq_bound = Eigen::VectorXd::Constant(1, 2.0);
  EXPECT_NO_THROW(prepareLog(jointsSource(writeJointsLog("ok.csv", {})), slow_robot));
}

// Column names that state an angle unit other than the one given are warned about (and named
// first when the speeds are refused); the unit they state, given, is silent.
TEST(Prepare, ColumnNamesThatSayDegreesAreNamedWhenReadAsRadians) {
  std::string text = readFile(writeLog(0.0));
  text.replace(0, text.find('\n'), "time_ms,q_a[deg],q_b[deg],tau_a,tau_b");
  const std::string path = test::tempPath("named_deg.csv");
  writeFileAtomically(path, text);
  const auto warned = [](const PrepareOutcome& out) {
    for (const std::string& w : out.warnings)
      if (w.find("'q_a[deg]' says degrees") != std::string::npos) return true;
    return false;
  };
  EXPECT_FALSE(warned(prepareLog(tableSource(path), msAndDegrees())));
  PrepareOptions as_radians = msAndDegrees();
  as_radians.angle_scale = 1.0;
  as_radians.dq_bound = Eigen::VectorXd::Constant(1, 1e3);  // past the plausibility check
  as_radians.ddq_bound = Eigen::VectorXd::Constant(1, 1e5);
  EXPECT_TRUE(warned(prepareLog(tableSource(path), as_radians)));
  as_radians.dq_bound = Eigen::VectorXd::Constant(1, 1.0);  // the speeds refused: named first
  const std::string message = inputError([&] { prepareLog(tableSource(path), as_radians); });
  EXPECT_NE(message.find("First: the column 'q_a[deg]' says degrees"), std::string::npos)
      << message;
}

// Rest at the ends is measured and warned about, with the window that crops it; the window keeps
// only its samples and is recorded.
TEST(Prepare, RestAtTheEndsIsWarnedAboutAndAWindowCropsIt) {
  JointsLog log;
  log.rest = 3.0;
  const std::string path = writeJointsLog("rest.csv", log);
  const PrepareOutcome o = prepareLog(jointsSource(path), {});
  ASSERT_EQ(o.rest.size(), 1u);
  // At rest until a joint moves 1 % of its range (6 mrad): about 0.1 s into the motion.
  EXPECT_NEAR(o.rest[0].leading, 3.1, 0.1);
  EXPECT_NEAR(o.rest[0].trailing, 3.1, 0.1);
  ASSERT_EQ(o.warnings.size(), 1u);
  EXPECT_NE(o.warnings[0].find("`window` 3."), std::string::npos) << o.warnings[0];
  PrepareOptions cropped;
  cropped.windows = {{2.9995, 7.0005}};  // rows 3001 to 7001, whatever the stamps' rounding
  const PrepareOutcome c = prepareLog(jointsSource(path), cropped);
  EXPECT_TRUE(c.warnings.empty()) << c.warnings.front();
  EXPECT_GE(c.train.time[0], 2.9995);
  EXPECT_LE(c.train.time[c.train.numSamples() - 1], 7.0005);
  EXPECT_LT(qError(c.train, log.rest, log.seconds), 1e-4);
  // Rows: the same window by data rows (row 1 is t = 0).
  PrepareOptions rows;
  rows.row_windows = {{3001, 7001}};
  const PrepareOutcome r = prepareLog(jointsSource(path), rows);
  EXPECT_EQ(r.train.time, c.train.time);
  EXPECT_EQ(r.train.tau, c.train.tau);
  // A window outside the log holds nothing: refused, not an empty dataset.
  PrepareOptions outside;
  outside.windows = {{3.0, 7.0}, {20.0, 30.0}};
  EXPECT_NE(inputError([&] { prepareLog(jointsSource(path), outside); }).find("holds no sample"),
            std::string::npos);
  // So does a held-out time range; the message gives the kept runs' span on the same axis.
  PrepareOptions held;
  held.validate_ranges = {{20.0, 30.0}};
  const std::string message = inputError([&] { prepareLog(jointsSource(path), held); });
  EXPECT_NE(message.find("`validate_time` 20:30 holds no sample: the kept runs span "),
            std::string::npos)
      << message;
  EXPECT_NE(message.find(" s from the log's first stamp"), std::string::npos) << message;
}

// The default rate is the log's nominal one (200 Hz, not its median step's 200.04 Hz, which the
// GC horizon then refuses); times start at the log's first stamp, kept exact from ns epochs.
TEST(Prepare, TheDefaultRateIsNominalAndTimeStartsAtTheFirstStampExactly) {
  JointsLog log;
  log.step = 1.0 / 200.043;
  const long long epoch = 1700000000123456789LL;  // ns: beyond a double's 53 bits
  log.stamp = [&](double t) { return std::to_string(epoch + std::llround(t * 1e9)); };
  PrepareOptions ns;
  ns.time_scale = 1e-9;
  const PrepareOutcome o = prepareLog(jointsSource(writeJointsLog("epoch.csv", log)), ns);
  EXPECT_EQ(o.rate, 200.0);
  EXPECT_NE(o.rate_reason.find("nominal"), std::string::npos) << o.rate_reason;
  // To the nanosecond (a double holds this epoch to 240 ns).
  EXPECT_LT(std::abs(static_cast<double>(o.time_origin - static_cast<long double>(epoch) * 1e-9L)),
            1e-9);
  // The first output sample: the default trim (2 / 10 Hz) after the first stamp, on the grid.
  EXPECT_NEAR(o.train.time[0], 0.2, 1e-12);
  EXPECT_NEAR(o.train.time[1] - o.train.time[0], 1.0 / 200.0, 1e-15);
  // A rate far from any nominal one stays the median's.
  JointsLog odd;
  odd.step = 1.0 / 337.7;
  const PrepareOutcome p = prepareLog(jointsSource(writeJointsLog("odd.csv", odd)), {});
  EXPECT_NEAR(p.rate, 337.7, 1e-6);
}

// keep_raw_torque: the held-out part's torques as logged (noise and all, never filtered or
// resampled) at the log's own jittered stamps, where two adjacent held-out samples bracket them;
// the training part's raw samples are not kept. Samples come as arrays (Python's prepare(t=...)).
TEST(Prepare, KeepsTheHeldOutRawTorquesAtTheLogsOwnStamps) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-2e-4, 2e-4), noise(-0.05, 0.05);
  auto raw = std::make_shared<RawSignals>();
  const int samples = 3000;  // 3 s at about 1 kHz
  raw->n = 1;
  raw->rows = samples;
  raw->values.resize(samples, 3);
  for (int k = 0; k < samples; ++k) {
    const double t = 1e-3 * k + (k > 0 ? jitter(random) : 0.0);
    raw->values.row(k) << t, std::sin(2.0 * t), std::cos(2.0 * t) + noise(random);
  }
  raw->ddq_at = 3;
  raw->file = raw->tau_file = "arrays";
  raw->line_of = [](Eigen::Index k) { return static_cast<int>(k + 1); };
  LogSource source;
  source.arrays = raw;
  PrepareOptions o;
  o.rate = 1000.0;
  o.cutoff = 5.0;
  o.validate_fraction = 0.25;
  o.keep_raw_torque = true;
  const PrepareOutcome out = prepareLog(source, o);
  const double from = out.validate.time[0], to = out.validate.time[out.validate.numSamples() - 1];
  int expected = 0;
  for (int k = 0; k < samples; ++k)
    expected += raw->values(k, 0) >= from && raw->values(k, 0) <= to;
  ASSERT_EQ(out.raw_validate_time.size(), expected);
  ASSERT_GT(expected, 500);  // a quarter of 3 s at 1 kHz, less the end the filter trims
  for (Eigen::Index i = 0, k = 0; i < out.raw_validate_time.size(); ++i) {
    while (raw->values(k, 0) < out.raw_validate_time[i]) ++k;
    EXPECT_EQ(out.raw_validate_time[i], raw->values(k, 0));
    EXPECT_EQ(out.raw_validate_tau(i, 0), raw->values(k, 2));  // as logged: noise included
  }
  // Nothing to keep without a held-out part.
  o.validate_fraction = 0.0;
  EXPECT_THROW(prepareLog(source, o), InputError);
}

// The joints are prepared on threads: the same outcome, bit for bit, on one thread and on three
// (filtered, torque filtered on its own, central differences and Savitzky-Golay, held out).
TEST(Prepare, JointsOnThreadsGiveTheSameBitsAsOnOne) {
  JointsLog log;
  log.joints = 5;
  const LogSource source = jointsSource(writeJointsLog("threads.csv", log));
  PrepareOptions plain;
  plain.validate_fraction = 0.25;
  PrepareOptions own_tau = plain;
  own_tau.tau_cutoff = 4.0;
  PrepareOptions savgol = plain;
  savgol.savitzky_golay = true;
  for (const PrepareOptions& o : {plain, own_tau, savgol}) {
    const PrepareOutcome one = prepareLog(source, o, 1), three = prepareLog(source, o, 3);
    for (const auto& [a, b] :
         {std::pair{&one.train, &three.train}, {&one.validate, &three.validate}}) {
      ASSERT_GT(a->numSamples(), 0);
      EXPECT_EQ(a->time, b->time);
      for (auto member : {&Trajectory::q, &Trajectory::dq, &Trajectory::ddq, &Trajectory::tau})
        EXPECT_EQ(a->*member, b->*member);
    }
    EXPECT_EQ(one.tau_noise, three.tau_noise);
    ASSERT_GT(one.excerpt_raw.size(), 0);
    EXPECT_EQ(one.excerpt_raw, three.excerpt_raw);
    EXPECT_EQ(one.excerpt_filtered, three.excerpt_filtered);
  }
}

// The datasets kept in scratch files (as dynid prepare keeps them, whatever the log's length) hold
// the numbers kept in memory, bit for bit: two runs, held-out samples inside each run (a time
// range) and at its end, both derivative methods, joints on threads.
TEST(Prepare, ScratchDatasetsHoldTheSameBitsAsMemory) {
  const LogSource source = tableSource(writeLog(0.05));
  PrepareOptions central = msAndDegrees();
  central.validate_fraction = 0.2;
  central.validate_ranges = {{1.0, 1.5}};
  PrepareOptions savgol = central;
  savgol.savitzky_golay = true;
  const std::string dir = test::tempPath("scratch");
  std::filesystem::create_directories(dir);
  for (const PrepareOptions& o : {central, savgol}) {
    const PrepareOutcome memory = prepareLog(source, o, 3);
    const PrepareOutcome scratch = prepareLog(source, o, 3, dir);
    ASSERT_EQ(memory.runs.size(), 2u);
    EXPECT_EQ(scratch.train.numSamples(), 0);
    ASSERT_TRUE(scratch.scratch_train && scratch.scratch_validate);
    EXPECT_EQ(scratch.warnings, memory.warnings);
    EXPECT_EQ(scratch.tau_noise, memory.tau_noise);
    for (const auto& [a, b] : {std::pair{&memory.train, scratch.scratch_train.get()},
                               {&memory.validate, scratch.scratch_validate.get()}}) {
      test::expectSameSamples(*a, b, 100);
      Trajectory chunk;
      b->rows(37, 90, chunk);  // a block from the middle
      EXPECT_EQ(chunk.tau, a->tau.middleCols(37, 53));
      EXPECT_EQ(b->column(ScratchDataset::kDdq, 1), a->ddq.row(1).transpose());
    }
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));  // the scratch files went with the outcomes
}

}  // namespace
}  // namespace dynid
