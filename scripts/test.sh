#!/usr/bin/env bash
# Quick start, step 2 (and what CI runs): install what is missing, build everything with the tests,
# benchmarks and the Python module, run the whole test suite (its pytest files included), then the
# sanitizer and fuzz jobs (scripts/sanitize.sh: a clang ASan+UBSan build, its unit and bad-input
# tests, 10 s of each fuzz target).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
# Ninja (installed above) for a new build directory: it schedules the two builds' ~400 objects
# and links better than make; a directory configured before keeps its generator.
generator=()
if [ ! -f build/CMakeCache.txt ] || grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' build/CMakeCache.txt; then
  generator=(-G Ninja)
fi
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DDYNID_BUILD_TESTS=ON \
  -DDYNID_BUILD_BENCH=ON -DDYNID_PYTHON=ON
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)"
./scripts/sanitize.sh
