#!/usr/bin/env bash
# The rows of the fit measured (docs/IDENTIFIABILITY.md, "The rows of the fit"): 20 simulated PUMA
# 560 logs with their drives' friction (60 s, Fourier motion, seeds 1-20, 0.5 N m of torque noise),
# through prepare's defaults (10 Hz low-pass) and OLS; how many 95 % intervals hold the truth
# (estimate.json's model_value), and the friction's errors. About 1 min 40 s on 2 cores.
#   examples/rows/run.sh [DYNID] [OUT_DIR]
set -euo pipefail
dynid=${1:-$(cd "$(dirname "$0")" && pwd)/../../build/bin/dynid}
out=${2:-rows-out}
mkdir -p "$out"
for seed in $(seq 1 20); do
  "$dynid" simulate --robot puma560 --drives --controller fourier --duration 60 --seed "$seed" \
    --noise-q 1e-5 --noise-tau 0.5 --out "$out/sim$seed.csv" >/dev/null
  "$dynid" prepare --log "$out/sim$seed.csv" --q 'q*' --tau 'tau*' --out "$out/prep$seed" >/dev/null
  "$dynid" identify --method ols --robot puma560 --drives --data "$out/prep$seed/train.csv" \
    --out "$out/est$seed" >/dev/null
done
python3 - "$out" <<'PY'
import json, statistics, sys
out = sys.argv[1]
inside = total = inertial_in = inertial = 0
coulomb = {j: [] for j in range(1, 7)}
viscous = {j: [] for j in range(1, 7)}
for seed in range(1, 21):
    with open(f"{out}/est{seed}/estimate.json") as f:
        estimate = json.load(f)
    for b in estimate["base_parameters"]:
        holds = abs(b["estimate"] - b["model_value"]) <= 1.959964 * b["std_dev"]
        inside += holds
        total += 1
        name = b["name"]
        if not name.startswith(("Fc", "Fv", "Fa", "Ia")):
            inertial_in += holds
            inertial += 1
        error = abs(b["estimate"] / b["model_value"] - 1) if b["model_value"] else None
        if name[:2] == "Fc" and name[2:].isdigit():
            coulomb[int(name[2:])].append(error)
        if name[:2] == "Fv" and name[2:].isdigit():
            viscous[int(name[2:])].append(error)
print(f"95 % intervals holding the truth: {inside} of {total} ({100 * inside / total:.1f} %), "
      f"inertial {inertial_in} of {inertial} ({100 * inertial_in / inertial:.1f} %)")
for label, table in (("Fc", coulomb), ("Fv", viscous)):
    print(label, "median / largest error per joint [%]:",
          ", ".join(f"{100 * statistics.median(v):.2f} / {100 * max(v):.2f}"
                    for v in table.values() if v))
PY
