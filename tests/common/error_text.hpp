// The message an error leaves: for tests that check what a refusal names (file, offset, field).
#pragma once

#include <string>

#include "core/errors.hpp"

namespace dynid::test {

/// The what() of the E that `f` throws, or "" when it throws none.
template <class E = ParseError, class F>
std::string errorText(F f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

}  // namespace dynid::test
