// One run control for every long computation (GC evaluations, searches, refinements, excitation
// design, studies): a stop flag (Ctrl-C), a deadline (a time budget) and a progress hook. A
// computation that honours it stops at its next check and returns its best result so far.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <string>

namespace dynid {

struct RunControl {
  using Clock = std::chrono::steady_clock;
  const std::atomic<bool>* stop = nullptr;                // set (SIGINT) to stop at the next check
  Clock::time_point deadline = Clock::time_point::max();  // the end of a time budget
  std::function<void(const std::string&)> progress;       // one line per stage
  /// Called by check() on the thread that runs the computation, before the flag is read (e.g. to
  /// turn a pending Python KeyboardInterrupt into `stop`); must not throw.
  std::function<void()> on_check;

  /// The stop flag is set. Safe from any thread.
  bool interrupted() const { return stop != nullptr && stop->load(std::memory_order_relaxed); }
  /// The deadline has passed. Safe from any thread.
  bool expired() const { return deadline != Clock::time_point::max() && Clock::now() >= deadline; }
  /// Interrupted or expired. Safe from any thread.
  bool stopped() const { return interrupted() || expired(); }
  /// on_check, then stopped(): for the computation's own thread, at an iteration's end.
  bool check() const {
    if (on_check) on_check();
    return stopped();
  }
  void say(const std::string& line) const {
    if (progress) progress(line);
  }
  /// A copy whose deadline is also at most `seconds` after `from` (seconds not > 0 or not
  /// finite: the deadline is unchanged).
  RunControl within(double seconds, Clock::time_point from = Clock::now()) const {
    RunControl out = *this;
    if (seconds > 0.0 && std::isfinite(seconds))
      out.deadline =
          std::min(deadline, from + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(std::min(seconds, 1e9))));
    return out;
  }
};

}  // namespace dynid
