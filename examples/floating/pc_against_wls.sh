#!/usr/bin/env bash
# pc against wls on a floating base whose model is off (docs/FLOATING.md, "Physically consistent"):
# ANYmal C and Romeo standing, their data made by a robot 10 % heavier than the model (every
# link's mass and inertia times 1.1, the centres of mass unchanged), identified with the model's
# URDF; each set's error against the heavier robot, in percent and in sd.
#   examples/floating/pc_against_wls.sh build/bin/dynid OUT_DIR
set -euo pipefail
dynid=$(realpath "$1")
out=$2
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
python3 - "$here" "$out" <<'PY'
import re, sys
here, out = sys.argv[1], sys.argv[2]
for src, name in [("anymal_c/anymal.urdf", "anymal"), ("romeo/romeo_small.urdf", "romeo")]:
    text = open(f"{here}/{src}").read()
    heavier = re.sub(r'\b(value|ixx|ixy|ixz|iyy|iyz|izz)="([-0-9.eE+]+)"',
                     lambda m: f'{m.group(1)}="{float(m.group(2)) * 1.1!r}"', text)
    open(f"{out}/{name}_heavier.urdf", "w").write(heavier)
PY
for robot in anymal romeo; do
  if [ "$robot" = anymal ]; then
    urdf=$here/anymal_c/anymal.urdf; contacts=LF_FOOT,RF_FOOT,LH_FOOT,RH_FOOT; samples=300
    noise=(--noise-tau 0.5 --noise-force 2)
  else
    urdf=$here/romeo/romeo_small.urdf; contacts=l_sole:frame,r_sole:frame; samples=200
    noise=(--noise-tau 0.5 --noise-force 5 --noise-moment 0.5)
  fi
  truth=$out/${robot}_heavier.urdf
  for seed in 1 2; do
    "$dynid" simulate --robot "$truth" --floating-base --contacts "$contacts" --samples "$samples" \
      --drive-terms fv --seed "$seed" "${noise[@]}" --out "$out/$robot-$seed.csv" > /dev/null
  done
  # The heavier robot's own base parameters (its model values), in the same combinations.
  "$dynid" identify --robot "$truth" --floating-base --drive-terms fv --data "$out/$robot-1.csv" \
    --out "$out/$robot-truth" > /dev/null
  for method in wls pc; do
    "$dynid" identify --robot "$urdf" --floating-base --drive-terms fv --method "$method" \
      --data "$out/$robot-1.csv" --validate "$out/$robot-2.csv" --out "$out/$robot-$method" > /dev/null
  done
done
python3 - "$out" <<'PY'
import json, math, sys
out = sys.argv[1]
print("| robot | method | set | base | residual % | held out % | from the truth % | z RMS | from the model % |")
print("|---|---|---|---|---|---|---|---|---|")
for robot in ["anymal", "romeo"]:
    truth = json.load(open(f"{out}/{robot}-truth/floating_identification.json"))
    for method in ["wls", "pc"]:
        doc = json.load(open(f"{out}/{robot}-{method}/floating_identification.json"))
        for s, t in zip(doc["sets"], truth["sets"]):
            if s["refused"]:
                continue
            est = [p["estimate"] for p in s["base_parameters"]]
            sd = [p["sd"] for p in s["base_parameters"]]
            true = [p["model_value"] for p in t["base_parameters"]]
            error = math.dist(est, true) / math.hypot(*true)
            z = math.sqrt(sum(((a - b) / c) ** 2 for a, b, c in zip(est, true, sd)) / len(est))
            print(f"| {robot} | {method} | {s['sensors']} | {s['num_base']} | "
                  f"{s['residual_percent']:.3g} | {s['validation_percent']:.3g} | {100 * error:.3g} | "
                  f"{z:.3g} | {s['model_error_percent']:.3g} |")
PY
