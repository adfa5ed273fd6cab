#!/usr/bin/env bash
# The paper's comparison on the Panda's real log: every method (ols, wls, pc, nlo, ga, hybrid, the
# refinements and combined) measured on torques and on motion prediction, training and held out.
#   examples/panda/study.sh [DYNID] [OUT_DIR]
# Run examples/panda/run.sh first (it prepares OUT_DIR/data). About 5 minutes on 2 cores: three
# 30 s searches and three refinements of at most 60 s.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
dynid=${1:-$here/../../build/bin/dynid}
out=${2:-panda-out}
"$dynid" study --robot panda --drive-terms fv,fc,fo \
  --data "$out/data/train.csv" --validate "$out/data/validate.csv" --out "$out/study"
