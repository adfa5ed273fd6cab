#include "core/memory.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {

namespace {

/// A "Key:  123 kB" line of a /proc file, in bytes; NaN when absent.
double procKilobytes(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.compare(0, key.size(), key) == 0 && line.size() > key.size() &&
        line[key.size()] == ':') {
      std::istringstream fields(line.substr(key.size() + 1));
      double kb = NAN;
      if (fields >> kb) return kb * 1024.0;
    }
  return NAN;
}

/// The first number of a one-line file (cgroup v2), NaN when absent or "max".
double fileNumber(const char* file) {
  std::ifstream in(file);
  double x = NAN;
  if (!(in >> x)) return NAN;
  return x;
}

}  // namespace

MemoryBudget memoryBudget() {
  MemoryBudget out{std::numeric_limits<double>::infinity(), ""};
  const auto consider = [&](double bytes, const char* limit) {
    if (std::isfinite(bytes) && bytes < out.bytes) out = {std::max(bytes, 0.0), limit};
  };
  const double size = procKilobytes("/proc/self/status", "VmSize");
  for (const auto& [resource, name] :
       {std::pair{RLIMIT_AS, "ulimit -v"}, std::pair{RLIMIT_DATA, "ulimit -d"}}) {
    rlimit limit{};
    if (::getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
        std::isfinite(size))
      consider(static_cast<double>(limit.rlim_cur) - size, name);
  }
  consider(fileNumber("/sys/fs/cgroup/memory.max") - fileNumber("/sys/fs/cgroup/memory.current"),
           "the cgroup's memory.max");
  const double available = procKilobytes("/proc/meminfo", "MemAvailable");
  const double swap = procKilobytes("/proc/meminfo", "SwapFree");
  consider(available + (std::isfinite(swap) ? swap : 0.0), "the machine's available memory");
  return out;
}

std::string formatBytes(double bytes) {
  const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 1000.0 && u < 5) {
    bytes /= 1000.0;
    ++u;
  }
  return formatNumber(u == 0 ? std::round(bytes) : bytes, u == 0 ? 0 : 3) + " " + units[u];
}

void requireMemory(double bytes, const std::string& what) {
  const MemoryBudget budget = memoryBudget();
  if (!(bytes > budget.bytes)) return;
  throw InputError(what + " needs " + formatBytes(bytes) + "; this process may use at most " +
                   formatBytes(budget.bytes) + " more (" + budget.limit + ")");
}

}  // namespace dynid
