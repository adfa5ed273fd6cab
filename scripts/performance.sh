#!/usr/bin/env bash
# docs/PERFORMANCE.md in one command: installs the benchmark peers (Orocos KDL, MuJoCo) when
# missing, builds the benchmarks in Release, and runs them. The peer table (dynid against KDL and
# MuJoCo on the same model, checked equal first) prints at the end of the first benchmark.
# Run it on an idle machine: the ratios come from one run, and each benchmark is single-threaded
# unless its name says threads:2.
set -euo pipefail
cd "$(dirname "$0")/.."
DYNID_WITH_PEERS=1 ./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDYNID_BUILD_BENCH=ON > /dev/null
cmake --build build -j"$(nproc)" --target bench_peers bench_core bench_search bench_identification
build/bench/bench_peers --benchmark_repetitions=5 --benchmark_report_aggregates_only
build/bench/bench_core --benchmark_repetitions=5 --benchmark_report_aggregates_only
build/bench/bench_search --benchmark_repetitions=3 --benchmark_report_aggregates_only
build/bench/bench_identification --benchmark_repetitions=3 --benchmark_report_aggregates_only \
  --benchmark_filter='Regressor|IdentifyPuma|samples:(1000|10000|100000)$'
build/bench/bench_identification --benchmark_filter='samples:1000000$'
