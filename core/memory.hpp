// Size checks before large allocations: how much memory this process may still use, and an error
// that says what is too large and what the limit is, instead of std::bad_alloc after the fact.
#pragma once

#include <cstdint>
#include <string>

namespace dynid {

/// What this process may still allocate, in bytes, and what bounds it.
struct MemoryBudget {
  double bytes = 0.0;  // +inf when nothing could be read
  std::string limit;   // "ulimit -v", "the cgroup's memory.max", "available memory" or ""
};

/// The smallest of: the address-space limit (RLIMIT_AS, `ulimit -v`) less the current size, the
/// data-segment limit (RLIMIT_DATA) less the same, the cgroup's memory.max less memory.current,
/// and MemAvailable plus SwapFree from /proc/meminfo. Reads /proc and /sys; never throws.
MemoryBudget memoryBudget();

/// Throws InputError when `bytes` exceed memoryBudget(): "<what> needs 5.8 GB; this process may
/// use at most 0.5 GB more (ulimit -v)". `what` names the data (file, samples) and the structure.
void requireMemory(double bytes, const std::string& what);

/// "5.8 GB", "412 MB", "12 kB": bytes for messages.
std::string formatBytes(double bytes);

}  // namespace dynid
