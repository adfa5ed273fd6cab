#!/usr/bin/env bash
# Pinocchio beside dynid, in one run (docs/PERFORMANCE.md): WHAT is `regressor` (the joint torque
# regressor on the PUMA 560, "The regressor"), `dynamics` (CRBA, ABA and an RK4 step on the PUMA
# 560 and the Panda, "dynid against Pinocchio") or `floating` (free-flyer inverse dynamics,
# regressor and mass matrix on ANYmal C and Romeo, examples/floating/, each loaded by its own URDF
# parser: Pinocchio's src/parsers/urdf with Debian's urdfdom, "Floating bases").
# Usage: scripts/pinocchio-bench.sh PINOCCHIO_SOURCE [BUILD_DIR] [WHAT]
# PINOCCHIO_SOURCE is a Pinocchio source tree (3.7.0 measured: git clone --branch v3.7.0
# https://github.com/stack-of-tasks/pinocchio); only its include/ is used, header-only, with the
# three headers its CMake would generate replaced by minimal stand-ins. Needs Boost's headers
# (libboost-dev) and Google Benchmark; dynid's Release build in BUILD_DIR (default build) for the
# side-by-side run. Runs the two benchmarks interleaved, four rounds of five repetitions (WHAT
# defaults to regressor).
set -euo pipefail
cd "$(dirname "$0")/.."
usage="usage: scripts/pinocchio-bench.sh PINOCCHIO_SOURCE [BUILD_DIR] [regressor|dynamics|floating]"
source_dir=${1:?$usage}
build_dir=${2:-build}
what=${3:-regressor}
case "$what" in
  regressor) dynid_bench=bench_identification filter='BM_Regressor/' ;;
  dynamics) dynid_bench=bench_core filter='BM_(Crba|CrbaPanda|Aba/drives:0|AbaPanda|Rk4Step|Rk4StepPanda)$' ;;
  floating) dynid_bench=bench_floating filter='BM_Floating' ;;
  *) echo "$usage" >&2; exit 2 ;;
esac
[ -f "$source_dir/include/pinocchio/fwd.hpp" ] || { echo "$source_dir: no include/pinocchio/fwd.hpp" >&2; exit 1; }
[ -x "$build_dir/bench/$dynid_bench" ] || { echo "$build_dir/bench/$dynid_bench: build dynid's benchmarks first (-DDYNID_BUILD_BENCH=ON)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/include/pinocchio"
cat > "$work/include/pinocchio/config.hpp" <<'H'
#pragma once
#define PINOCCHIO_DLLAPI
#define PINOCCHIO_LOCAL
#define PINOCCHIO_MAJOR_VERSION 3
#define PINOCCHIO_MINOR_VERSION 7
#define PINOCCHIO_PATCH_VERSION 0
#define PINOCCHIO_VERSION "3.7.0"
H
cat > "$work/include/pinocchio/warning.hpp" <<'H'
#pragma once
#define PINOCCHIO_WARNING(x)
H
cat > "$work/include/pinocchio/deprecated.hpp" <<'H'
#pragma once
#define PINOCCHIO_DEPRECATED __attribute__((deprecated))
#define PINOCCHIO_DEPRECATED_MESSAGE(message) __attribute__((deprecated(message)))
H
extra=()
if [ "$what" = floating ]; then
  # Pinocchio's URDF parser: two sources of its own, its generated config header, and urdfdom
  # (Debian's 3.x: std::shared_ptr and its own pointer typedefs, as Pinocchio's CMake detects).
  mkdir -p "$work/include/pinocchio/parsers"
  printf '#pragma once\n#define PINOCCHIO_PARSERS_DLLAPI\n' > "$work/include/pinocchio/parsers/config.hpp"
  extra=(-DPINOCCHIO_URDFDOM_TYPEDEF_SHARED_PTR -DPINOCCHIO_URDFDOM_USE_STD_SHARED_PTR
         "$source_dir/src/parsers/urdf/model.cpp" "$source_dir/src/parsers/urdf/utils.cpp"
         -lurdfdom_model)
fi
g++ -std=c++20 -O3 -DNDEBUG -Wno-deprecated-declarations -I. -I"$work/include" -I"$source_dir/include" \
  -I/usr/include/eigen3 "bench/pinocchio/$what.cpp" "${extra[@]}" -o "$work/pinocchio_$what" \
  -lbenchmark -lpthread
for round in 1 2 3 4; do
  "$work/pinocchio_$what" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true |
    grep median
  "$build_dir/bench/$dynid_bench" --benchmark_filter="$filter" \
    --benchmark_repetitions=5 --benchmark_report_aggregates_only=true | grep median
done
