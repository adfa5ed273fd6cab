// A small fixed pool of worker threads for data-parallel loops. Results must be written per index
// (never accumulated across threads) so that they do not depend on the thread count.
#pragma once

#include <signal.h>

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace dynid {

/// The thread count that means every hardware thread: the default of every request's and front
/// end's `threads` (--threads, threads=) that does not say otherwise.
inline constexpr int kAllThreads = 0;

/// While it lives, SIGINT, SIGTERM and SIGHUP are blocked on the calling thread (its mask is
/// restored after), so the threads it starts meanwhile inherit the block and such a signal is
/// handled on a thread that started none (the main one). A handler that removes the temporaries
/// of files being written (data/io.hpp) then never runs beside the thread that creates them.
/// Programs a blocked thread starts must reset their mask (posix_spawnattr_setsigmask).
class TerminationSignalsBlocked {
 public:
  TerminationSignalsBlocked();
  ~TerminationSignalsBlocked();
  TerminationSignalsBlocked(const TerminationSignalsBlocked&) = delete;
  TerminationSignalsBlocked& operator=(const TerminationSignalsBlocked&) = delete;

 private:
  sigset_t previous_;
};

/// Its workers start with the termination signals blocked (TerminationSignalsBlocked).
class ThreadPool {
 public:
  static constexpr int kMaxThreads = 1024;
  /// num_threads >= 1 (the calling thread is one of them); 0 means all hardware threads. Throws
  /// InputError above kMaxThreads, and Error (after joining those that started) when the system
  /// refuses to create a thread.
  explicit ThreadPool(int num_threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int numThreads() const { return static_cast<int>(workers_.size()) + 1; }

  /// Calls body(index, thread) for index in [0, count), thread in [0, numThreads()); each thread
  /// takes the next unclaimed index, so which thread runs an index varies from call to call.
  /// Returns when all are done. body must not throw. Not re-entrant.
  void parallelFor(int count, const std::function<void(int, int)>& body);

 private:
  void workerLoop(int thread);
  void stopAndJoin();
  void runIndices(int thread);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  const std::function<void(int, int)>* body_ = nullptr;
  int count_ = 0;
  alignas(64) std::atomic<int> next_{0};  // the next unclaimed index, on its own cache line
  alignas(64) long generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
};

}  // namespace dynid
