#!/usr/bin/env bash
# The GC error in identify's report (docs/FLOATING.md, "In identify's report"): ANYmal C 10 %
# heavier than its URDF (every link's mass and inertia times 1.1), suspended on a stand tilted to
# three orientations (upright, 0.4 rad of roll, 0.4 rad of pitch: --stand-tilts), each holding a
# 10 s design (`dynid excite` of the robot with its base fixed, seed 1 for training and 2 held out)
# sampled at 1 kHz; noise at two levels; identified with the URDF (wls, pc, combined: pc refined
# to predict the motion too, without a time budget) and with the heavier robot itself.
#   examples/floating/gc_in_identify.sh build/bin/dynid OUT_DIR
set -euo pipefail
dynid=$(realpath "$1")
out=$2
here=$(cd "$(dirname "$0")" && pwd)
urdf=$here/anymal_c/anymal.urdf
mkdir -p "$out"
cd "$out"
python3 "$here/heavier_urdf.py" "$urdf" anymal_heavier.urdf 1.1
for s in 1 2; do
  "$dynid" excite --robot "$urdf" --drive-terms fv --seed "$s" --out "excite$s" > /dev/null
done
for level in high low; do
  if [ "$level" = high ]; then
    noise=(--noise-tau 0.5 --noise-force 2 --noise-moment 0.5)
  else
    noise=(--noise-tau 0.05 --noise-force 0.2 --noise-moment 0.05)
  fi
  for s in 1 2; do
    "$dynid" simulate --robot anymal_heavier.urdf --floating-base --trajectory \
      "excite$s/excitation.json" --stand-tilts 0,0,0.4,0,0,0.4 --samples 10000 \
      --drive-terms fv --seed "$s" "${noise[@]}" --out "$level$s.csv" > /dev/null
  done
  for method in wls pc combined; do
    echo "== noise $level, the URDF, $method"
    budget=()
    [ "$method" = combined ] && budget=(--combined-seconds 0)
    "$dynid" identify --robot "$urdf" --floating-base --drive-terms fv --method "$method" \
      "${budget[@]}" --data "${level}1.csv" --validate "${level}2.csv" --out "$level-$method" \
      2> /dev/null | grep -v "^wrote\|base's RMS"
  done
  echo "== noise $level, the heavier robot itself, wls"
  "$dynid" identify --robot anymal_heavier.urdf --floating-base --drive-terms fv \
    --data "${level}1.csv" --validate "${level}2.csv" --out "$level-truth" 2> /dev/null | sed -n 2,5p
done
