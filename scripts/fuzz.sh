#!/usr/bin/env bash
# Long fuzzing runs: scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]
#   SECONDS_PER_TARGET defaults to 3600; TARGETs default to all (dataset_csv raw_log model_json
#   urdf manifest search_json checkpoint estimate_json excitation_json). Uses the sanitizer build (build-asan/, made
#   by scripts/sanitize.sh's configuration) and keeps each target's growing corpus in
#   build-asan/fuzz/corpus_<target>, so runs add up. Runs DYNID_FUZZ_JOBS libFuzzer processes (-fork; default one per core).
#   A crash, hang (10 s) or blow-up (2 GB) is written to build-asan/fuzz/crashes/ and stops that
#   target; reproduce it with build-asan/fuzz/fuzz_<target> <file>, then add the input to
#   tests/fuzz/corpus/<target>/ with the fix. A line per target goes to build-asan/fuzz/log.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${DYNID_ASAN_BUILD:-build-asan}
seconds=${1:-3600}
jobs=${DYNID_FUZZ_JOBS:-$(nproc)}  # fuzzing processes (default: one per core)
shift || true
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(dataset_csv raw_log model_json urdf manifest search_json checkpoint estimate_json excitation_json)
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=None \
    -DCMAKE_CXX_FLAGS="-O1 -g1 -DEIGEN_NO_DEBUG" -DDYNID_SANITIZE=ON -DDYNID_FUZZ=ON -DDYNID_BUILD_BENCH=OFF
fi
cmake --build "$build" -j"$(nproc)" --target $(printf 'fuzz_%s ' "${targets[@]}")
mkdir -p "$build/fuzz/crashes"
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp"
for t in "${targets[@]}"; do
  corpus="$build/fuzz/corpus_$t"
  mkdir -p "$corpus"
  echo "fuzz.sh: $t for ${seconds} s, $jobs processes"
  start=$(date +%s)
  status=0
  "$build/fuzz/fuzz_$t" -fork="$jobs" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -dict=tests/fuzz/dynid.dict -artifact_prefix="$build/fuzz/crashes/${t}-" \
    "$corpus" "tests/fuzz/corpus/$t" 2>&1 | tee "$build/fuzz/$t.out" | grep -E "^#|ERROR|DONE" || status=$?
  end=$(date +%s)
  execs=$(grep -oE "^#[0-9]+" "$build/fuzz/$t.out" | tail -n 1 | tr -d '#' || true)
  echo "$(date -u +%FT%TZ) $t $((end - start)) s x $jobs processes, ${execs:-0} inputs run," \
    "corpus $(ls "$corpus" | wc -l) inputs, $(grep -c "ERROR" "$build/fuzz/$t.out" || true) errors" \
    >> "$build/fuzz/log.txt"
done
tail -n "${#targets[@]}" "$build/fuzz/log.txt"
