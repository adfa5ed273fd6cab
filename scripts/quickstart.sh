#!/usr/bin/env bash
# Quick start, step 1: install what is missing, build dynid, and run the main job, `dynid demo`, on
# the built-in PUMA 560 (about 2 to 3 minutes on 2 cores; the report goes to out/demo/).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target dynid
build/bin/dynid demo --out out/demo
