#!/usr/bin/env bash
# The Franka Emika Panda identified from Gaz et al.'s real log with dynid alone:
#   examples/panda/run.sh [DYNID] [LOG_DIR] [OUT_DIR]
# DYNID defaults to build/bin/dynid, LOG_DIR to ../shared/data/panda_gaz2019 beside the
# repository, OUT_DIR to panda-out. Numbers and what each step does: examples/panda/README.md.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
dynid=${1:-$here/../../build/bin/dynid}
log=${2:-$here/../../../shared/data/panda_gaz2019}
out=${3:-panda-out}
mkdir -p "$out"

# 1. The raw log (one value per line, irregular stamps, no ddq) into train and held-out datasets:
#    resampled to 1 kHz, q and tau zero-phase filtered at 5 Hz, dq and ddq by central
#    differences, the last 20 % of the log held out. The 8.5 ms stalls are bridged (--max-gap).
"$dynid" prepare --time-file "$log/exciting_traj_time.txt" \
  --q-file "$log/exciting_traj_positions.txt" --tau-file "$log/exciting_traj_torques.txt" \
  --joints 7 --rate 1000 --cutoff 5 --max-gap 0.02 --validate-fraction 0.2 --out "$out/data"

# 2. The built-in Panda with the published drive model (link-side torque sensors: fv, fc, fo).
for method in ols wls pc; do
  "$dynid" identify --method "$method" --robot panda --drive-terms fv,fc,fo \
    --data "$out/data/train.csv" --validate "$out/data/validate.csv" --out "$out/$method"
done

# 3. The OLS estimate applied to the held-out part: predicted torques, errors and the figure of
#    measured against predicted torque for every joint (panda-out/predict/torques.svg).
"$dynid" predict --estimate "$out/ols/estimate.json" --data "$out/data/validate.csv" \
  --out "$out/predict"

# 4. The physically consistent estimate written back into a URDF of the Panda.
"$dynid" model export --robot panda --format urdf --out "$out/panda.urdf"
"$dynid" identify --method pc --robot "$out/panda.urdf" --drive-terms fv,fc,fo \
  --data "$out/data/train.csv" --out "$out/pc-urdf" --write-urdf "$out/panda_identified.urdf"
"$dynid" model check --robot "$out/panda_identified.urdf"
