#!/usr/bin/env bash
# Quick start, step 1: install what is missing, build dynid and its Python module (build/python),
# and run the main job, `dynid demo`, on the built-in PUMA 560 (the report goes to out/demo/).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDYNID_PYTHON=ON
cmake --build build -j"$(nproc)" --target dynid dynid_python
build/bin/dynid demo --out out/demo
