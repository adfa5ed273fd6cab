#!/usr/bin/env bash
# pc and combined on a simulated arm with torque noise, against the truth (docs/REFINEMENT.md,
# "The combined estimator"):
#   examples/combined/run.sh DYNID ROBOT DRIVE_TERMS BANDWIDTH NOISE_TAU OUT_DIR [SEED]
#   e.g. examples/combined/run.sh build/bin/dynid panda fv,fc,fo 2 0.5 combined-panda
#        examples/combined/run.sh build/bin/dynid puma560 none 5 0.05 combined-puma
# Also the front (identify --method combined --front, the estimate chosen on the held-out data;
# docs/REFINEMENT.md, "The front"). SEED (default 2) seeds the training noise, SEED + 1 the
# held-out run's.
# 30 s of the default sinusoids for training, 10 s of a Fourier motion held out; the prior is the
# truth with every link scaled by its own factor in [0.8, 1.2] (models.py). About 30 s on 2 cores.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
dynid=$1 robot=$2 terms=$3 bandwidth=$4 noise=$5 out=$6 seed=${7:-2}
mkdir -p "$out"
"$dynid" model export --robot "$robot" --drive-terms "$terms" --format json --out "$out/export.json" >/dev/null
python3 "$here/models.py" "$robot" "$out/export.json" "$out/truth.json" "$out/prior.json"
sim=(--robot "$out/truth.json" --drive-terms "$terms" --bandwidth "$bandwidth")
"$dynid" simulate "${sim[@]}" --duration 30 --noise-tau "$noise" --noise-q 1e-5 --seed "$seed" --out "$out/train.csv" >/dev/null
"$dynid" simulate "${sim[@]}" --duration 30 --seed "$seed" --out "$out/train_clean.csv" >/dev/null
"$dynid" simulate "${sim[@]}" --duration 10 --controller fourier --amplitude 0.5 --noise-tau "$noise" \
  --noise-q 1e-5 --seed $((seed + 1)) --out "$out/validate.csv" >/dev/null
"$dynid" identify --method ols --robot "$out/truth.json" --drive-terms "$terms" \
  --data "$out/train_clean.csv" --out "$out/truth_ols" >/dev/null
for method in pc combined; do
  "$dynid" identify --method "$method" --robot "$out/prior.json" --drive-terms "$terms" \
    --data "$out/train.csv" --validate "$out/validate.csv" --out "$out/$method" >/dev/null
done
"$dynid" identify --method combined --front --robot "$out/prior.json" --drive-terms "$terms" \
  --data "$out/train.csv" --validate "$out/validate.csv" --out "$out/front" >/dev/null
python3 "$here/compare.py" "$out"
