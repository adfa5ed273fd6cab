#!/usr/bin/env bash
# docs/REFINEMENT.md's noise study: does estimating the segment starts (chained, multiple
# shooting) give a lower base-parameter error than taking the noisy measured starts as exact?
# Per seed: 5 s of the PUMA 560 with noise 1e-4 rad on q and 1e-3 rad/s on dq, every
# non-overlapping 50 ms segment (100, contiguous), a start 10 % off the truth (a one-evaluation
# GA), then `dynid refine` with and without --estimate-initial-states (one thread each, the two in
# parallel). Prints a Markdown table. Usage: scripts/refine-noise-study.sh [OUT_DIR] [SEEDS...]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/noise-study}
shift || true
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(1 2 3 4 5)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j"$(nproc)" --target dynid > /dev/null
dynid=build/bin/dynid
mkdir -p "$out"
value() {  # value FILE KEY: the number after "KEY": at the top level of FILE (one-space indent)
  sed -n "s/^ \"$2\": \([-0-9.eE+]*\).*/\1/p" "$1" | head -1
}
base_stage_error() {  # the base stage's base_parameter_error (two-space indent)
  sed -n "s/^  \"base_parameter_error\": \([-0-9.eE+]*\).*/\1/p" "$1" | head -1
}
echo "| seed | final, measured starts | final, estimated starts | base stage, measured | base stage, estimated | seconds (measured / estimated) |"
echo "|---|---|---|---|---|---|"
for s in "${seeds[@]}"; do
  d="$out/seed-$s"
  mkdir -p "$d"
  "$dynid" simulate --robot puma560 --duration 5 --seed "$s" --noise-q 1e-4 --noise-dq 1e-3 \
    --out "$d/train.csv" > /dev/null
  "$dynid" search --method ga --robot puma560 --data "$d/train.csv" --perturb 0.1 --seed "$s" \
    --population 4 --budget-evals 1 --segments 0 --out "$d/start" > /dev/null
  common=(refine --robot puma560 --from "$d/start/search.json" --data "$d/train.csv"
    --truth puma560 --threads 1)
  "$dynid" "${common[@]}" --out "$d/measured" > "$d/measured.log" 2>&1 &
  "$dynid" "${common[@]}" --estimate-initial-states --out "$d/estimated" > "$d/estimated.log" 2>&1
  wait
  m="$d/measured/refine.json" e="$d/estimated/refine.json"
  echo "| $s | $(value "$m" final_base_parameter_error) | $(value "$e" final_base_parameter_error)" \
    "| $(base_stage_error "$m") | $(base_stage_error "$e")" \
    "| $(value "$m" seconds) / $(value "$e" seconds) |"
done
