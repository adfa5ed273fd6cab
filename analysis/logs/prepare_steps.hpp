// The steps of dynid prepare (prepare.cpp) that live in rooms of their own, for prepare.cpp alone
// (an internal header, not installed): the stamps (units, sorting, stalls, windows, runs;
// stamps.cpp), the spectra and the filter's choice (filter.cpp), and the plausibility check
// (plausible.cpp).
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "analysis/logs/prepare.hpp"
#include "analysis/logs/read_log.hpp"
#include "core/signal.hpp"
#include "core/trajectory.hpp"

namespace dynid::prepare_steps {

/// The resampled samples a run writes: first, first + step, ... (size() of them), without a
/// vector an hour long.
struct RowList {
  int first = 0, step = 1;
  std::size_t count = 0;
  int operator[](std::size_t r) const { return first + static_cast<int>(r) * step; }
  std::size_t size() const { return count; }
  int front() const { return first; }
  int back() const { return (*this)[count - 1]; }
};

/// Consecutive samples of one file without a gap, and where its output goes.
struct RunSpan {
  std::size_t file = 0;
  Eigen::Index begin = 0, end = 0;  // [begin, end) in the file's samples
  PreparedRun run;                  // file and time offset set
  int count = 0, edge = 0;          // resampled samples; trimmed at each end
  bool kept = false;                // long enough for the filter
  RowList rows;                     // the resampled samples written (trimmed, decimated)
  std::vector<char> held;           // per row: 1 when it goes to the validate set
  /// The train and validate sets' samples of the run's first row in each: its rows of either set
  /// follow one another from there.
  Eigen::Index first_slot[2] = {0, 0};
};

// The most samples a log is resampled to, over all its runs (about 14 h at 1 kHz), and the most
// per logged sample: beyond either, --rate is a mistake and the work would run for hours.
inline constexpr double kMaxResampledSamples = 5e7;
inline constexpr double kMaxUpsampling = 100.0;

/// The low-passes: q's (and dq's, ddq's) and tau's (the same unless --tau-cutoff says otherwise).
struct Filters {
  std::vector<Biquad> q, tau;
  bool tau_as_q = true;
  /// The filter that measures the torque noise: q's, else tau's.
  const std::vector<Biquad>& noise() const { return q.empty() ? tau : q; }
};

/// The trajectory's matrix holding `signal` (the time: none; tau's, unused).
inline Eigen::MatrixXd Trajectory::*matrixOf(ScratchDataset::Signal signal) {
  switch (signal) {
    case ScratchDataset::kQ:
      return &Trajectory::q;
    case ScratchDataset::kDq:
      return &Trajectory::dq;
    case ScratchDataset::kDdq:
      return &Trajectory::ddq;
    default:
      return &Trajectory::tau;
  }
}

/// Keeps the rows `kept` (increasing) in place.
void compact(RawSignals& s, const std::vector<Eigen::Index>& kept);

/// The log's signals in SI units: time and angles scaled, motor currents times torque constant
/// and gear ratio.
void applyUnits(RawSignals& out, const LogSource& source, const PrepareOptions& options);

double median(std::vector<double> v);

/// Sorts by time (stable) and keeps the first sample of each repeated stamp; counts both. A stamp
/// that goes back further than the gap limit (`max_gap`, or 5 median forward steps) is not jitter
/// but a clock reset or a second recording appended: sorting would interleave two recordings, so
/// it is a ParseError naming the line.
void sortAndDeduplicate(RawSignals& s, double max_gap, PrepareOutcome& out);

/// Drops stalled repeats (PrepareOptions::keep_stalled): within each stretch of samples identical
/// to its first, the repeats go when the stretch ends within `max_gap` of its first stamp.
void dropStalled(RawSignals& s, double max_gap, PrepareOutcome& out);

std::vector<double> steps(const RawSignals& s);

std::string resampleBoundMessage(double samples, double raw, double rate);

int resampledCount(const RawSignals& s, const RunSpan& span, double rate);

/// Column `column` of the signals over the span, resampled to the uniform rate: `count` samples
/// from the span's `first` resampled sample on.
Eigen::VectorXd resampled(const RawSignals& s, const RunSpan& span, Eigen::Index column,
                          double rate, int count, int first = 0);

/// Spectra of q and tau over every run at least one segment long (each joint normalised to unit
/// power, then summed), the trajectory band and the noise edge.
void measureSpectra(const std::vector<RawSignals>& files, const std::vector<RunSpan>& spans,
                    PrepareOutcome& out);

/// Chooses the cutoff (and says why), the trim and the Savitzky-Golay window.
void chooseFilter(const PrepareOptions& options, PrepareOutcome& out);

/// Keeps the data rows in `windows` (1-based, in file order), before anything reorders them; the
/// line numbers follow.
void keepRows(RawSignals& s, const std::vector<std::pair<long, long>>& windows,
              const std::string& label);

/// Keeps the samples within `windows` [s] (times from the log's first stamp).
void keepWindows(RawSignals& s, const std::vector<std::pair<double, double>>& windows,
                 std::vector<char>& held);

/// The nominal rate near `rate` (the median step's): the nearest round rate (a whole number of Hz
/// below 100 Hz, of 10 Hz above) or round step (a whole number of 0.1 ms: 3 ms is 333.33 Hz),
/// when within 0.1 % of it; else `rate` itself. Says which.
double nominalRate(double rate, std::string& reason);

/// A q or dq column whose name states another angle unit than the one given (e.g.
/// "AxisPos_A1[deg]" read as radians), as "'NAME' says UNIT", or "".
std::string angleUnitMismatch(const std::vector<LogColumns>& files, double angle_scale);

/// Where each recording rests (or creeps) at its ends, with a warning when that is 10 % of it or
/// more: rest identifies gravity and offsets only and outweighs the motion in a least-squares fit.
void findRest(const std::vector<RawSignals>& files, const std::vector<std::string>& labels,
              PrepareOutcome& out);

/// Pass 1: stalls dropped, steps measured, later files shifted after earlier ones, and the runs
/// between gaps.
std::vector<RunSpan> findRuns(std::vector<RawSignals>& files, const PrepareOptions& options,
                              PrepareOutcome& out);

void checkPlausible(const PrepareOptions& options, int n, bool ddq_meaningful, PrepareOutcome& out);

/// Stamps counted from the log's first one, exactly (differences of the 64-bit stamps: epochs in
/// ns): the `first` file's earliest stamp (before any window) sets out.time_origin, later files
/// are shifted to it.
void alignToLogTime(RawSignals& s, const PrepareOptions& options, bool first, PrepareOutcome& out);

/// Why a file (`label`) has fewer than 3 distinct stamps: within the windows given, and what the
/// log spans.
std::string fewStampsMessage(const std::string& label, const PrepareOptions& options,
                             double spans_from, double spans_to);

/// From out.median_step: refuses a step no robot log has (naming the `first` file; the time unit
/// is the likely fault) and sets the resampling rate (given, or the nominal rate near the median
/// step's) and the gap limit.
void chooseRate(const std::string& first, const PrepareOptions& options, PrepareOutcome& out);

/// The low-passes of the chosen cutoffs (out.cutoff, out.tau_cutoff; chooseFilter's), each
/// refused at or above the output rate's Nyquist frequency.
Filters designFilters(const PrepareOptions& options, const PrepareOutcome& out);

}  // namespace dynid::prepare_steps
