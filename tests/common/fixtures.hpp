// Where the tests' committed fixture files are.
#pragma once

#include <filesystem>

namespace dynid::test {

/// The recordings written by independent writers (provenance: tests/data/bags/fixtures/README.md).
inline const std::filesystem::path kBagFixtures =
    std::filesystem::path(DYNID_SOURCE_DIR) / "tests/data/bags/fixtures";

}  // namespace dynid::test
