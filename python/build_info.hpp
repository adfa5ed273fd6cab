// The commit the Python module was built from (generated at build time by
// cmake/build_info.cmake; "unknown" outside a git checkout), as its documents' provenance records.
#pragma once

namespace dynid::python {

extern const char* const kBuildCommit;

}  // namespace dynid::python
