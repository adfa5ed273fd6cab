// core/memory: the budget follows the process's address-space limit, and requireMemory refuses
// what does not fit with a message naming the data, the size and the limit.
#include "core/memory.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "core/errors.hpp"

namespace dynid {
namespace {

TEST(Memory, FormatsBytesForMessages) {
  EXPECT_EQ(formatBytes(512), "512 bytes");
  EXPECT_EQ(formatBytes(12e3), "12 kB");
  EXPECT_EQ(formatBytes(5.76e9), "5.76 GB");
}

TEST(Memory, TheBudgetIsFiniteOnLinuxAndSmallAllocationsPass) {
  const MemoryBudget budget = memoryBudget();
  EXPECT_TRUE(std::isfinite(budget.bytes));  // /proc/meminfo is always there on Linux
  EXPECT_GT(budget.bytes, 1e6);
  EXPECT_NO_THROW(requireMemory(1e3, "a kilobyte"));
}

TEST(Memory, FollowsTheAddressSpaceLimitAndNamesIt) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "a sanitizer's shadow memory does not fit under an address-space limit";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  GTEST_SKIP() << "a sanitizer's shadow memory does not fit under an address-space limit";
#endif
#endif
  // In a child: the limit is its current size plus 200 MB, so about 200 MB remain.
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    rlimit now{};
    ::getrlimit(RLIMIT_AS, &now);
    // The child's current size (VmSize), which the limit counts.
    std::FILE* status = std::fopen("/proc/self/status", "r");
    char line[256];
    double vm_kb = 0.0;
    while (status != nullptr && std::fgets(line, sizeof(line), status) != nullptr)
      if (std::sscanf(line, "VmSize: %lf", &vm_kb) == 1) break;
    if (status != nullptr) std::fclose(status);
    const rlimit limit{static_cast<rlim_t>(vm_kb * 1024.0 + 200e6), now.rlim_max};
    if (vm_kb <= 0.0 || ::setrlimit(RLIMIT_AS, &limit) != 0) ::_exit(10);
    const MemoryBudget budget = memoryBudget();
    // 200 MB less what the child mapped since reading VmSize (a few pages at most).
    if (!(budget.bytes <= 200e6 && budget.bytes > 150e6)) ::_exit(11);
    if (budget.limit != "ulimit -v") ::_exit(12);
    try {
      requireMemory(1e9, "data.csv: 2000000 samples");
      ::_exit(13);
    } catch (const InputError& e) {
      const std::string m = e.what();
      if (m.find("data.csv: 2000000 samples needs 1 GB") == std::string::npos ||
          m.find("ulimit -v") == std::string::npos)
        ::_exit(14);
    }
    try {
      requireMemory(1e6, "a megabyte");
    } catch (...) {
      ::_exit(15);
    }
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "10: no limit set, 11: budget, 12: limit name, "
                                       "13: no throw, 14: message, 15: a small request refused";
}

}  // namespace
}  // namespace dynid
