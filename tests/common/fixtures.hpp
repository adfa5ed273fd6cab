// Where the tests' committed fixture files are.
#pragma once

#include <filesystem>

namespace dynid::test {

/// The recordings written by independent writers (provenance: tests/data/bags/fixtures/README.md).
/// A function, not a namespace-scope path: a test source's own namespace-scope paths built from it
/// would otherwise depend on the initialisation order of an inline variable, which clang 14 does
/// not keep (the sanitizer build's conformance test read an empty folder).
inline std::filesystem::path bagFixtures() {
  return std::filesystem::path(DYNID_SOURCE_DIR) / "tests/data/bags/fixtures";
}

}  // namespace dynid::test
