#include "core/parallel.hpp"

#include <algorithm>
#include <string>
#include <system_error>

#include "core/errors.hpp"

namespace dynid {

TerminationSignalsBlocked::TerminationSignalsBlocked() {
  sigset_t termination;
  sigemptyset(&termination);
  for (int signal : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&termination, signal);
  pthread_sigmask(SIG_BLOCK, &termination, &previous_);
}

TerminationSignalsBlocked::~TerminationSignalsBlocked() {
  pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
}

ThreadPool::ThreadPool(int num_threads) {
  if (num_threads <= 0) num_threads = std::max(1u, std::thread::hardware_concurrency());
  if (num_threads > kMaxThreads)
    throw InputError("at most " + std::to_string(kMaxThreads) + " threads, not " +
                     std::to_string(num_threads));
  workers_.reserve(static_cast<std::size_t>(num_threads - 1));
  try {
    const TerminationSignalsBlocked inherited;
    for (int t = 1; t < num_threads; ++t) workers_.emplace_back([this, t] { workerLoop(t); });
  } catch (const std::system_error& e) {
    // The system would not create another thread (a process or memory limit): stop and join the
    // ones that started, so nothing waits on them, and say so.
    const std::size_t started = workers_.size();
    stopAndJoin();
    throw Error("could not start " + std::to_string(num_threads) + " threads (the system " +
                "refused after " + std::to_string(started + 1) + "): " + e.what() +
                "; use fewer `threads`");
  }
}

ThreadPool::~ThreadPool() { stopAndJoin(); }

void ThreadPool::stopAndJoin() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (std::thread& w : workers_) w.join();
  workers_.clear();
}

void ThreadPool::runIndices(int thread) {
  // Dynamic scheduling: each thread takes the next unclaimed index, so a thread that runs slower
  // (a busy core, a virtual CPU that loses time) takes fewer. The results do not depend on which
  // thread ran an index, because the body writes per index.
  for (int i = next_.fetch_add(1, std::memory_order_relaxed); i < count_;
       i = next_.fetch_add(1, std::memory_order_relaxed))
    (*body_)(i, thread);
}

void ThreadPool::parallelFor(int count, const std::function<void(int, int)>& body) {
  if (workers_.empty() || count <= 1) {
    for (int i = 0; i < count; ++i) body(i, 0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    body_ = &body;
    count_ = count;
    pending_ = static_cast<int>(workers_.size());
    next_.store(0, std::memory_order_relaxed);
    ++generation_;
  }
  start_.notify_all();
  runIndices(0);
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [this] { return pending_ == 0; });
  body_ = nullptr;
}

void ThreadPool::workerLoop(int thread) {
  long seen = 0;
  while (true) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    runIndices(thread);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --pending_;
    }
    done_.notify_one();
  }
}

}  // namespace dynid
