#include "core/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
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

}  // namespace
}  // namespace dynid
