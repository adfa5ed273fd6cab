#!/usr/bin/env bash
# A standing robot's excitation, designed (docs/FLOATING.md, "Designing a standing sway"): ANYmal C
# standing on its four feet, knees bent; its sway designed from the URDF (`dynid excite
# --floating-base`, the feet's forces within cones of mu 0.6), the robot 10 % heavier than the URDF
# (every link's mass and inertia times 1.1) simulated along it with noise (seed 1 for training, 2
# held out), then identified with the URDF by wls and pc: what each sensor set estimates, and how
# far from the heavier robot.
#   examples/floating/standing_design.sh build/bin/dynid OUT_DIR
set -euo pipefail
dynid=$(realpath "$1")
out=$2
here=$(cd "$(dirname "$0")" && pwd)
urdf=$here/anymal_c/anymal.urdf
mkdir -p "$out"
cd "$out"
python3 "$here/heavier_urdf.py" "$urdf" anymal_heavier.urdf 1.1
"$dynid" excite --robot "$urdf" --floating-base --contacts LF_FOOT,RF_FOOT,LH_FOOT,RH_FOOT \
  --stance 0,0.5,-1,0,0.5,-1,0,-0.5,1,0,-0.5,1 --friction-cone 0.6 --out design
for s in 1 2; do
  "$dynid" simulate --robot anymal_heavier.urdf --floating-base \
    --trajectory design/standing_excitation.json --friction-cone 0.6 --noise-tau 0.05 \
    --noise-force 0.2 --noise-moment 0.05 --seed "$s" --out "standing$s.csv" > /dev/null
done
for method in wls pc; do
  echo "== the URDF, $method"
  "$dynid" identify --robot "$urdf" --floating-base --data standing1.csv --validate standing2.csv \
    --method "$method" --out "$method" 2> /dev/null | grep -v "^wrote"
done
# wls's estimate does not depend on the parameters of the robot read (only on its structure): read
# with the heavier robot, its "from the model" is the estimate's distance from the truth.
echo "== the heavier robot itself, wls"
"$dynid" identify --robot anymal_heavier.urdf --floating-base --data standing1.csv \
  --validate standing2.csv --out truth 2> /dev/null | grep -v "^wrote"
