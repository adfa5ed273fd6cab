// The commit the dynid executable was built from (generated at build time by
// cmake/build_info.cmake; "unknown" outside a git checkout).
#pragma once

namespace dynid::cli {

extern const char* const kBuildCommit;

}  // namespace dynid::cli
