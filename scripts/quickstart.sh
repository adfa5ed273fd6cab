#!/usr/bin/env bash
# Quick start, step 1: install what is missing, build dynid, and run the main job on the built-in
# PUMA 560 (until `dynid demo` exists: simulate a training dataset and print the dynamics at a pose).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target dynid
mkdir -p out
build/bin/dynid simulate --robot puma560 --duration 10 --seed 1 --out out/puma_train.csv
build/bin/dynid dynamics --robot puma560 --q 0,0.7853981633974483,3.141592653589793,0,0.7853981633974483,0 \
  --dq 0.5,-0.3,0.2,0.1,-0.4,0.6
