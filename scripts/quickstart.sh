#!/usr/bin/env bash
# Quick start, step 1: install what is missing, build dynid and its Python module (build/python),
# and run the main job, `dynid demo`, on the built-in PUMA 560 (the report goes to out/demo/).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
# A unity build (CMake's batches of up to 8 sources per translation unit): a whole build compiles
# each shared header once per batch instead of once per source (scripts/test.sh says how much).
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDYNID_PYTHON=ON -DCMAKE_UNITY_BUILD=ON
cmake --build build -j"$(nproc)" --target dynid dynid_python
build/bin/dynid demo --out out/demo
