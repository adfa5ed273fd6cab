#!/usr/bin/env bash
# Quick start, step 2 (and what CI runs): install what is missing, build everything with the tests,
# benchmarks and the Python module, run the whole test suite (its pytest files included), then the
# sanitizer and fuzz jobs (scripts/sanitize.sh: a clang ASan+UBSan build, its unit and bad-input
# tests, 10 s of each fuzz target).
set -euo pipefail
cd "$(dirname "$0")/.."
# Each step's wall time on stderr at its end (docs/TOUR.md keeps what they were on a clean clone).
last=$SECONDS
took() { echo "test.sh: $1 took $((SECONDS - last)) s" >&2; last=$SECONDS; }
./scripts/install-deps.sh
took "installing packages"
# Ninja (installed above) for a new build directory: it schedules the two builds' ~400 objects
# and links better than make; a directory configured before keeps its generator.
generator=()
if [ ! -f build/CMakeCache.txt ] || grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' build/CMakeCache.txt; then
  generator=(-G Ninja)
fi
# A unity build: each target's sources compiled in batches of up to 8 (CMake's default), so the
# headers they share (Eigen, Ceres, nlohmann-json, the dynamics templates) are parsed and
# instantiated once per batch (docs/CI.md has what it saves).
# Incremental work is faster without it (-DCMAKE_UNITY_BUILD=OFF: one source recompiled, not its
# batch). The rollouts compiled for AVX2 and AVX-512 stay translation units of their own
# (search/CMakeLists.txt).
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DDYNID_BUILD_TESTS=ON \
  -DDYNID_BUILD_BENCH=ON -DDYNID_PYTHON=ON -DCMAKE_UNITY_BUILD=ON
cmake --build build -j"$(nproc)"
took "the release build"
ctest --test-dir build --output-on-failure -j"$(nproc)"
took "the release suite"
./scripts/sanitize.sh
took "the sanitizer build, suite and fuzz targets"
