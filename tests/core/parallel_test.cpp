#include "core/parallel.hpp"

#include <signal.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "core/errors.hpp"

namespace dynid {
namespace {

TEST(ThreadPool, RunsEveryIndexOnceOnAValidThread) {
  for (const int threads : {1, 2, 4}) {
    ThreadPool pool(threads);
    for (int round = 0; round < 20; ++round)
      for (const int count : {0, 1, 2, 7, 1000}) {
        std::vector<int> runs(count, 0), thread_of(count, -1);
        pool.parallelFor(count, [&](int i, int thread) {
          ++runs[i];
          thread_of[i] = thread;
        });
        for (int i = 0; i < count; ++i) {
          ASSERT_EQ(runs[i], 1) << threads << " threads, count " << count << ", index " << i;
          ASSERT_GE(thread_of[i], 0);
          ASSERT_LT(thread_of[i], threads);
        }
      }
  }
}

TEST(ThreadPool, ASlowThreadTakesFewerIndices) {
  // The worker blocks on its first index until the calling thread has run 30 of the 40 (or 5 s
  // have passed since the start, so that a pool that splits the indices in fixed halves fails
  // instead of hanging).
  ThreadPool pool(2);
  std::atomic<int> by_caller{0};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  pool.parallelFor(40, [&](int, int thread) {
    if (thread == 0) {
      ++by_caller;
      return;
    }
    while (by_caller < 30 && std::chrono::steady_clock::now() < deadline) {
    }
  });
  EXPECT_GE(by_caller.load(), 30);
}

// More threads than the pool allows is refused up front (thousands exhaust the process table; the
// pool used to deadlock when the system refused one), and a refused pool leaves nothing running.
TEST(ThreadPool, RefusesMoreThreadsThanItsLimit) {
  EXPECT_THROW(ThreadPool(ThreadPool::kMaxThreads + 1), InputError);
  EXPECT_THROW(ThreadPool(100000), InputError);
  ThreadPool most(8);
  EXPECT_EQ(most.numThreads(), 8);
}

bool blocked(int signal) {
  sigset_t mask;
  pthread_sigmask(SIG_BLOCK, nullptr, &mask);
  return sigismember(&mask, signal) == 1;
}

// A termination signal is handled on the thread that made the pool, never on a worker (where it
// would run beside the main thread's writes): the workers block it, the caller's mask is as it was.
TEST(ThreadPool, WorkersBlockTheTerminationSignalsTheCallerDoesNot) {
  ASSERT_FALSE(blocked(SIGTERM));
  ThreadPool pool(3);
  EXPECT_FALSE(blocked(SIGTERM) || blocked(SIGINT) || blocked(SIGHUP));
  std::vector<int> all_blocked(64, -1);
  pool.parallelFor(64, [&](int index, int thread) {
    if (thread > 0) all_blocked[index] = blocked(SIGTERM) && blocked(SIGINT) && blocked(SIGHUP);
    std::this_thread::sleep_for(std::chrono::microseconds(200));  // lets the workers take some
  });
  int on_workers = 0;
  for (int b : all_blocked)
    if (b >= 0) {
      EXPECT_EQ(b, 1);
      ++on_workers;
    }
  EXPECT_GT(on_workers, 0);
  {
    const TerminationSignalsBlocked scope;
    EXPECT_TRUE(blocked(SIGTERM));
  }
  EXPECT_FALSE(blocked(SIGTERM));
}

}  // namespace
}  // namespace dynid
