// Text checks the tests share.
#pragma once

#include <string>

namespace dynid::test {

/// Whether `fragment` occurs in `s`.
inline bool contains(const std::string& s, const std::string& fragment) {
  return s.find(fragment) != std::string::npos;
}

}  // namespace dynid::test
