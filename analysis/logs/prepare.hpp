// dynid prepare: a raw log in, a dynid dataset out (data/dataset_csv.hpp). The pipeline, per file
// and per run (samples between gaps):
//   read (analysis/logs/raw_log.hpp) -> units (degrees, time unit, motor current x torque constant
//   x gear ratio) -> sort by time, drop repeated stamps and stalled repeats -> split at gaps ->
//   resample to a uniform rate (linear) -> zero-phase Butterworth low-pass of q, dq and tau alike
//   ("parallel filtering") -> dq (when not logged, or asked) and ddq by central differences ->
//   trim the filter's edge transients -> decimate -> concatenate -> split train / validate (the
//   last fraction of each run, whole runs, time ranges).
// Several tables are separate recordings: each is its own runs, never resampled, filtered or
// differentiated across a file boundary.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "analysis/logs/read_log.hpp"
#include "core/signal.hpp"
#include "core/trajectory.hpp"
#include "data/scratch.hpp"

namespace dynid {

struct PrepareOptions {
  double time_scale = 1.0;   // seconds per time unit (ms: 1e-3)
  double angle_scale = 1.0;  // radians per angle unit of q and dq (deg: pi/180)
  /// Output rate before decimation [Hz]; 0: the log's median rate, rounded to its nominal rate
  /// (a whole number of Hz, or of 0.1 ms steps) when within 0.1 % of it.
  double rate = 0.0;
  /// Low-pass -3 dB frequency [Hz] (single pass); 0: no filter; < 0: 10 Hz, or a quarter of the
  /// rate for logs slower than 40 Hz.
  double cutoff = -1.0;
  /// Choose the cutoff from q's spectrum instead (cutoff ignored): five times the trajectory band
  /// (the frequency below which 99.5 % of q's power lies, every joint weighted alike), but below
  /// where q's spectrum meets its noise floor and at most a quarter of the rate.
  bool auto_cutoff = false;
  /// Torque's own low-pass [Hz]: < 0: q's (parallel filtering, the default); 0: none (the raw
  /// resampled torque, as papers validate against); > 0: its own cutoff (same order).
  double tau_cutoff = -1.0;
  int order = 4;            // Butterworth order
  int decimate = 1;         // keep every Nth sample
  double max_gap = 0.0;     // split the log at larger steps [s]; 0: 5 median steps
  double trim = -1.0;       // dropped at each run's ends [s]; < 0: 2 / cutoff
  bool derive_dq = false;   // dq from q even when dq is logged
  bool derive_ddq = false;  // ddq from dq (or q) even when ddq is logged
  /// Derivatives by central differences, or by Savitzky-Golay polynomials of `savgol_degree` over
  /// `savgol_window` samples (odd; 0: the odd count nearest a quarter period of the cutoff, 10 Hz
  /// without a filter; at least degree + 2).
  bool savitzky_golay = false;
  int savgol_window = 0, savgol_degree = 3;
  double validate_fraction = 0.0;  // the last fraction of each run held out (0: none)
  std::vector<int> validate_runs;  // whole runs held out: 0-based among the kept runs, in order
  /// Held-out time ranges [from, to] in the output's time [s] (from the log's first stamp, plus
  /// any file offset).
  std::vector<std::pair<double, double>> validate_ranges;
  /// With LogSource::current: tau_j = current_j * torque_constants_j * gear_ratios_j (motor
  /// torque constant [N m/A] and gear ratio; the joint-side torque, drive losses left to the
  /// friction terms). One entry per joint each; gear ratios empty: 1.
  Eigen::VectorXd torque_constants, gear_ratios;
  /// The parts of the log kept, in seconds from its first stamp ([from, to], inclusive; several
  /// files: each one's stamps from the first file's first stamp); empty: all. Windows closer than
  /// the gap limit join into one run; each must hold samples.
  std::vector<std::pair<double, double>> windows;
  /// The data rows kept (1-based, inclusive, in the file's order; one log file only); empty: all.
  std::vector<std::pair<long, long>> row_windows;
  /// Plausibility bounds on the prepared |dq| and |ddq| [rad/s, rad/s^2; m/s, m/s^2 for prismatic
  /// joints]: one value for every joint or one per joint; empty: kPlausibleSpeed and
  /// kPlausibleAcceleration. The 99th percentile of a joint's magnitude above its bound is an
  /// InputError naming the likely cause (units or columns). ddq is checked only when filtered or
  /// logged (differences of an unfiltered q are mostly noise).
  Eigen::VectorXd dq_bound, ddq_bound;
  /// Samples whose every signal repeats the previous sample bit for bit while the stamp advances
  /// are a logger that stalled: dropped (the gap is bridged) when the stall is shorter than the
  /// gap limit; a longer identical stretch is the robot at rest and kept. true: keep them all.
  bool keep_stalled = false;
  /// Also keep the held-out part's raw torques (after units and torque constants, never filtered
  /// or resampled) at the log's own stamps, where the held-out samples bracket them
  /// (PrepareOutcome::raw_validate; prepare writes validate_raw.csv): predict and identify
  /// --validate then report the error against the measurement itself.
  bool keep_raw_torque = false;

  /// Throws InputError for a unit scale that is not positive or a numeric field out of its range
  /// (core/option_ranges.hpp, as dynid prepare's options, by field name). prepareLog checks its
  /// options first.
  void check() const;
};

/// What no robot does: joint speeds and accelerations beyond these come from a unit or column
/// mistake (degrees read as radians: 57 times; seconds read as milliseconds: 1000 times).
inline constexpr double kPlausibleSpeed = 50.0;           // [rad/s]
inline constexpr double kPlausibleAcceleration = 2000.0;  // [rad/s^2]
/// Median steps outside [kFastestStep, kSlowestStep] are not a robot's log in the given time
/// unit (above 100 kHz, or below 5 Hz where no dynamics can be identified).
inline constexpr double kFastestStep = 1e-5, kSlowestStep = 0.2;  // [s]

/// Where a recording rests (or creeps) at its ends: no joint has moved from its first (last)
/// position by more than max(1 mrad, 1 % of its range over the recording).
struct RestAtEnds {
  int file = 0;
  double start = 0.0, end = 0.0;         // the recording's first and last stamp [s]
  double leading = 0.0, trailing = 0.0;  // at rest from the start, and before the end [s]
};

/// One run of the log: consecutive samples without a gap.
struct PreparedRun {
  int file = 0;                      // index into LogSource::tables (0 for per-signal files)
  double start = 0.0, end = 0.0;     // [s], in the file's time
  double time_offset = 0.0;          // added to the file's time in the output [s]
  int raw_samples = 0, samples = 0;  // in and out (after trimming and decimation)
};

/// A prepared dataset kept in a scratch file (data/scratch.hpp) rather than in memory: the time,
/// then each joint's q, dq, ddq and tau, a column each. Written by prepareLog (each joint's
/// signals from its own thread), read back in blocks of rows.
class ScratchDataset {
 public:
  enum Signal { kTime = 0, kQ, kDq, kDdq, kTau };
  /// Throws Error when the scratch file cannot be made in `dir`.
  ScratchDataset(const std::string& dir, int num_joints, Eigen::Index samples);
  int numJoints() const { return n_; }
  Eigen::Index numSamples() const { return columns_.rows(); }
  /// values[0, count) as samples [first, first + count) of `signal` of joint `joint` (ignored for
  /// the time).
  void write(Signal signal, int joint, Eigen::Index first, const double* values,
             Eigen::Index count);
  /// Every sample of one signal.
  Eigen::VectorXd column(Signal signal, int joint) const;
  /// Samples [first, last) into `chunk` (resized), as DatasetRows (data/dataset_csv.hpp) asks.
  void rows(int first, int last, Trajectory& chunk) const;

 private:
  int index(Signal signal, int joint) const {
    return signal == kTime ? 0 : 1 + (signal - 1) * n_ + joint;
  }
  int n_ = 0;
  ScratchColumns columns_;
};

struct PrepareOutcome {
  /// The datasets (validate empty without a held-out part); both empty when prepareLog was given
  /// a scratch directory, which holds them in scratch_train and scratch_validate instead.
  Trajectory train, validate;
  std::shared_ptr<const ScratchDataset> scratch_train, scratch_validate;
  Eigen::Index trainSamples() const {
    return scratch_train ? scratch_train->numSamples() : train.numSamples();
  }
  Eigen::Index validateSamples() const {
    return scratch_validate ? scratch_validate->numSamples() : validate.numSamples();
  }
  /// The log's first stamp [s] (the first file's earliest, in its unit times the time scale, with
  /// 64-bit precision): every time in the output and in this outcome is the stamp minus it.
  long double time_origin = 0.0L;
  std::vector<LogColumns> columns;  // per table file: the columns read, in joint order
  std::vector<RestAtEnds> rest;     // per file
  std::vector<std::string> warnings;
  std::string rate_reason;  // how the rate was chosen, one sentence
  int raw_samples = 0, repeated_stamps = 0, unsorted_stamps = 0, stalled_repeats = 0;
  long skipped_missing = 0;  // rows left out for a missing value (LogSource::skip_missing)
  double median_step = 0.0, min_step = 0.0, max_step = 0.0;  // raw [s]
  std::vector<std::pair<double, double>> gaps;               // (at [s], length [s])
  std::vector<PreparedRun> runs;
  int runs_planned = 0;  // runs long enough for the filter (validate_runs index them)
  std::vector<PreparedRun> dropped_runs;  // runs shorter than the filter's transient
  double rate = 0.0, cutoff = 0.0, trim = 0.0, max_gap = 0.0;
  double tau_cutoff = 0.0;  // the torque's cutoff [Hz] (0: not filtered)
  int order = 0, decimate = 1;
  bool dq_derived = false;
  bool ddq_logged = false;    // the logged ddq, resampled and filtered, is used
  int savgol_window = 0;      // with Savitzky-Golay derivatives, the window used
  Eigen::VectorXd tau_noise;  // per joint: RMS of the resampled minus the filtered torque [N m]
  /// The cutoff's evidence, from the resampled runs before filtering: q's and tau's power spectra,
  /// each joint normalised to unit power and then summed (every joint counts alike).
  Spectrum q_spectrum, tau_spectrum;
  double trajectory_band = 0.0;  // 99.5 % of q's power lies below it [Hz]
  /// Above the band, where q's spectrum falls to 10x its noise floor (the median density from 10x
  /// the band to a quarter of the rate) [Hz].
  double noise_edge = 0.0;
  std::string cutoff_reason;  // how the cutoff was chosen, one sentence
  /// Up to 2 s from the middle of the longest run: the resampled torque before and after the
  /// filter (rows: samples; columns: joints) and the times.
  Eigen::VectorXd excerpt_time;
  Eigen::MatrixXd excerpt_raw, excerpt_filtered;
  /// With keep_raw_torque: the held-out raw torques (rows: samples in time order, on the output's
  /// time axis; columns: joints) where two adjacent held-out samples bracket their stamp.
  Eigen::VectorXd raw_validate_time;
  Eigen::MatrixXd raw_validate_tau;
};

/// Seconds per unit of "s", "ms", "us" or "ns"; radians per unit of "rad" or "deg". Throw
/// InputError naming the valid units.
double timeUnitScale(const std::string& unit);
double angleUnitScale(const std::string& unit);

/// Runs the pipeline. The rate, gap limit and cutoff defaults come from the median step over every
/// file (a median step outside [kFastestStep, kSlowestStep] is an InputError naming --time-unit).
/// Times count from the log's first stamp (PrepareOutcome::time_origin). A later file whose stamps
/// do not start after the previous file's end is shifted to start max(1 s, 2 gap limits) after it
/// (PreparedRun::time_offset). Throws ParseError for a malformed file (file, line, column),
/// InputError for inconsistent options (cutoff above Nyquist, a run shorter than the filter, no
/// sample left, currents without one torque constant per joint). The joints are resampled,
/// filtered and differentiated on `threads` threads (0: every hardware thread, at most 256; the
/// same bits for any count). `scratch_dir` empty: the datasets in PrepareOutcome::train and
/// validate; else in scratch files in that directory (PrepareOutcome::scratch_train and
/// scratch_validate, the same numbers): memory independent of their length (an hour at 1 kHz of a
/// 7-joint arm is 835 MB of doubles). Throws Error when the scratch files cannot be written.
PrepareOutcome prepareLog(const LogSource& source, const PrepareOptions& options, int threads = 0,
                          const std::string& scratch_dir = "");

}  // namespace dynid
