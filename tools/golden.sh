#!/usr/bin/env bash
# The golden set: one run of every command whose documents a refactoring must not change, with
# budgets in evaluations and iterations (not seconds) so two binaries give comparable bytes.
#   tools/golden.sh DYNID OUT_DIR [PANDA_LOG_DIR]
# Compare two runs with tools/golden_diff.py OLD_OUT NEW_OUT (timings removed).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
dynid=$(realpath "$1")
out=$2
log=$(realpath "${3:-$here/../../shared/data/panda_gaz2019}")
mkdir -p "$out"
cd "$out"
run() { echo "+ $*" >&2; "$dynid" "$@" > /dev/null; }

run simulate --robot puma560 --controller sinusoidal --frequency 0.2,0.3,0.4,0.5,0.6,0.7 \
  --amplitude 0.5 --duration 4 --dt 1e-3 --rate 200 --noise-q 1e-4 --noise-dq 1e-3 --seed 7 \
  --out train.csv
run simulate --robot puma560 --controller sinusoidal --frequency 0.25,0.35,0.45,0.55,0.65,0.75 \
  --amplitude 0.4 --duration 2 --dt 1e-3 --rate 200 --seed 8 --out test.csv
run identifiability --robot puma560 --drives --data train.csv --out ident
run model export --robot puma560 --drives --format json --out puma.json
run model export --robot panda --drives --format urdf --out panda.urdf
"$dynid" model show --robot panda --drives > model-show.txt
"$dynid" dynamics --robot puma560 --drives --q 0,0.785,3.14,0,0.785,0 --dq 0.1,0.2,0.3,-0.1,0,1 \
  --ddq 1,0,0,0,0,-1 --json > dynamics.json
for method in ols wls pc; do
  run identify --method "$method" --robot puma560 --data train.csv --validate test.csv \
    --threads 2 --out "id-$method"
done
run predict --estimate id-ols/estimate.json --data test.csv --out pred
for method in nlo ga hybrid; do
  run search --method "$method" --robot puma560 --data train.csv --perturb 0.3 --truth puma560 \
    --seed 3 --budget-evals 150 --segments 40 --threads 2 --out "search-$method"
done
# A checkpointed search stopped at 80 evaluations, then resumed to 150.
run search --method nlo --robot puma560 --data train.csv --perturb 0.3 --truth puma560 --seed 3 \
  --budget-evals 80 --segments 40 --threads 2 --checkpoint ckpt.json --out search-ckpt-a
run search --method nlo --robot puma560 --data train.csv --perturb 0.3 --truth puma560 --seed 3 \
  --budget-evals 150 --segments 40 --threads 2 --checkpoint ckpt.json --out search-ckpt-b
run refine --robot puma560 --from search-nlo/search.json --data train.csv --truth puma560 \
  --max-iterations 20 --threads 2 --out refine
run identify --method combined --robot puma560-consistent --data train.csv --validate test.csv \
  --combined-iterations 3 --combined-seconds 0 --segments 20 --threads 2 --out id-combined
run audit --estimates id-ols/estimate.json id-wls/estimate.json --out audit
# A push on joint 2, watched with thresholds from the clean held-out run.
run simulate --robot puma560 --controller sinusoidal --frequency 0.25,0.35,0.45,0.55,0.65,0.75 \
  --amplitude 0.4 --duration 4 --dt 1e-3 --rate 200 --noise-tau 0.05 --seed 9 \
  --disturbance joint=2,torque=10,at=2,for=0.2 --out pushed.csv
run monitor --arm id-ols/estimate.json --data pushed.csv --calibration test.csv \
  --truth pushed.truth.csv --out mon
# A payload: the training motion again with 1.5 kg more on the last link (its own model).
/usr/bin/python3 - <<'PY'
import json
model = json.load(open("puma.json"))
model["bodies"][-1]["inertial"]["m"] += 1.5
json.dump(model, open("puma-loaded.json", "w"))
PY
run simulate --robot puma-loaded.json --drives --controller sinusoidal \
  --frequency 0.2,0.3,0.4,0.5,0.6,0.7 --amplitude 0.5 --duration 4 --dt 1e-3 --rate 200 \
  --noise-q 1e-4 --noise-dq 1e-3 --seed 7 --out loaded.csv
run simulate --robot puma560 --drives --controller sinusoidal \
  --frequency 0.2,0.3,0.4,0.5,0.6,0.7 --amplitude 0.5 --duration 4 --dt 1e-3 --rate 200 \
  --noise-q 1e-4 --noise-dq 1e-3 --seed 7 --out unloaded.csv
run payload --arm puma.json --data loaded.csv --unloaded unloaded.csv --format ur,kuka \
  --out payload
# batch in two shards, merged.
run batch "$here/../examples/noise_study.json" --quick --shard 1/2 --jobs 1 --out shard1
run batch "$here/../examples/noise_study.json" --quick --shard 2/2 --jobs 1 --out shard2
run batch merge shard1 shard2 --out merged
# A ROS 1 bag of the training motion's JointState messages (python3-rosbag), prepared.
/usr/bin/python3 - <<'PY'
import csv
import rosbag
import rospy
from sensor_msgs.msg import JointState
with rosbag.Bag("run.bag", "w") as bag, open("train.csv") as f:
    rows = csv.reader(f)
    next(rows)
    for row in rows:
        v = [float(x) for x in row]
        m = JointState()
        m.header.stamp = rospy.Time.from_sec(100.0 + v[0])
        m.name = [f"joint{j}" for j in range(1, 7)]
        m.position, m.velocity, m.effort = v[1:7], v[7:13], v[19:25]
        bag.write("/joint_states", m, m.header.stamp)
PY
run prepare --log run.bag --robot puma560 --rate 200 --cutoff 20 --out bag
run excite --robot puma560 --starts 2 --evaluations 150 --harmonics 3 --seed 2 --out excite
run batch "$here/../examples/noise_study.json" --quick --jobs 2 --out batch
run demo --quick --search-evaluations 100 --threads 2 --out demo
if [[ -d "$log" ]]; then
  run prepare --time-file "$log/exciting_traj_time.txt" \
    --q-file "$log/exciting_traj_positions.txt" --tau-file "$log/exciting_traj_torques.txt" \
    --joints 7 --rate 1000 --cutoff 5 --max-gap 0.02 --validate-fraction 0.2 --out panda
  run study --robot panda --drive-terms fv,fc,fo --data panda/train.csv \
    --validate panda/validate.csv --search-evaluations 60 --refine-iterations 5 --segments 20 \
    --threads 2 --out panda-study
fi
echo "golden: $(find . -type f | wc -l) files in $out" >&2
