#include "core/format.hpp"

#include <algorithm>
#include <array>
#include <cctype>
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

bool naturalLess(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  const auto digit = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; };
  while (i < a.size() && j < b.size()) {
    if (digit(a[i]) && digit(b[j])) {
      std::size_t ei = i, ej = j;
      while (ei < a.size() && digit(a[ei])) ++ei;
      while (ej < b.size() && digit(b[ej])) ++ej;
      std::string x = a.substr(i, ei - i), y = b.substr(j, ej - j);
      x.erase(0, std::min(x.find_first_not_of('0'), x.size() - 1));
      y.erase(0, std::min(y.find_first_not_of('0'), y.size() - 1));
      if (x.size() != y.size()) return x.size() < y.size();
      if (x != y) return x < y;
      i = ei, j = ej;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

std::string progressText(double done_fraction, double elapsed_seconds) {
  const double f = std::isfinite(done_fraction) ? std::clamp(done_fraction, 0.0, 1.0) : 0.0;
  std::string text = std::to_string(static_cast<int>(std::floor(100.0 * f))) + " %";
  if (f <= 0.0 || f >= 1.0 || !(elapsed_seconds > 0.0)) return text;
  const long left = std::lround(elapsed_seconds * (1.0 - f) / f);
  text += ", about ";
  if (left >= 60) text += std::to_string(left / 60) + " min ";
  return text + std::to_string(left % 60) + " s left";
}

}  // namespace dynid
