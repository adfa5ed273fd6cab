#include "core/format.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace dynid {

std::string formatNumber(double x, int digits, const char* non_finite) {
  if (!std::isfinite(x) && non_finite != nullptr) return non_finite;
  std::array<char, 40> buffer;
  if (digits <= 0) {
    const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), x);
    return std::string(buffer.data(), result.ptr);
  }
  const int n = std::snprintf(buffer.data(), buffer.size(), "%.*g", digits > 17 ? 17 : digits, x);
  return std::string(buffer.data(), static_cast<std::size_t>(n));
}

}  // namespace dynid
