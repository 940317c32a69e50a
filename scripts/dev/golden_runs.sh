#!/usr/bin/env bash
# Golden runs for behaviour-preserving changes (docs/planner.md, "Golden runs"): records what a
# juggle binary prints and writes for a fixed set of deterministic commands, so that the same
# commands with a changed binary can be compared byte for byte.
#
#   scripts/dev/golden_runs.sh JUGGLE OUT [eval labels simulate train ppo guided_nopre]
#
# Run from the repository root whose configs match JUGGLE. Compare two OUT folders with
# `scripts/dev/golden_runs.sh --compare BEFORE AFTER`: wall-clock fields, output paths and
# `--planner-trace`'s cost terms (added by the task seam) are left out of the comparison.
set -uo pipefail
if [[ ${1:-} == -h || ${1:-} == --help || $# -lt 2 ]]; then
  sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
fi
if [[ $1 == --compare ]]; then
  a=$2 b=$3 status=0
  strip() { sed -E 's/  terms:.*//; s/wall_s=[0-9.]+ wall_s_per_sim_s=[0-9.]+//; s#(to|in) /[^ ]*##; s/steps\/s +[0-9]+//; s/sim s\/s +[0-9.]+//' "$1"; }
  for f in eval.txt labels.txt simulate.txt; do
    [[ -f $a/$f && -f $b/$f ]] || continue
    if diff -q <(strip "$a/$f") <(strip "$b/$f") >/dev/null; then echo "same: $f"; else echo "DIFFERENT: $f"; status=1; fi
  done
  for f in eval.jsonl demos.bin kicks.bin train/demos.jgld guided_nopre/demos.jgld; do
    [[ -f $a/$f && -f $b/$f ]] || continue
    if cmp -s "$a/$f" "$b/$f"; then echo "same: $f"; else echo "DIFFERENT: $f"; status=1; fi
  done
  for run in train ppo guided_nopre; do
    [[ -f $a/$run/metrics.jsonl && -f $b/$run/metrics.jsonl ]] || continue
    if /usr/bin/python3 - "$a/$run/metrics.jsonl" "$b/$run/metrics.jsonl" <<'PY'
import json, sys
clock = {'started_unix', 'iteration_s', 'samples_per_s', 'sim_s_per_s', 'train_s', 'update_s',
         'wait_s', 'checkpoint'}
a = [json.loads(l) for l in open(sys.argv[1])]
b = [json.loads(l) for l in open(sys.argv[2])]
same = len(a) == len(b) and all(
    {k: v for k, v in x.items() if k not in clock} == {k: v for k, v in y.items() if k not in clock}
    for x, y in zip(a, b))
sys.exit(0 if same else 1)
PY
    then echo "same: $run/metrics.jsonl (wall-clock fields and paths aside)"; else echo "DIFFERENT: $run/metrics.jsonl"; status=1; fi
  done
  exit $status
fi
J=$1; OUT=$2; shift 2
what=${*:-eval labels simulate train ppo guided_nopre}
mkdir -p "$OUT"
train() {  # NAME CONFIG
  rm -rf "$OUT/$1"
  $J train --config="$2" --iterations=3 --workers=1 --envs=4 --threads=1 --run_dir="$OUT/$1" \
    --metrics_port=0 > "$OUT/$1.txt" 2>&1
}
for w in $what; do case $w in
eval)  # 3 held-out starts x 10 s with every re-plan traced
  $J eval --controller=planner --config=configs/right_foot_planner.textproto --episodes=3 \
    --max_seconds=10 --planner-trace --json="$OUT/eval.jsonl" > "$OUT/eval.txt" 2>&1 ;;
labels)  # the teacher's labels and kick variables
  $J label-spread --config=configs/learning/guided_cheap_consistent.textproto --episodes=1 \
    --seconds=3 --forks=2 --dump-demos="$OUT/demos.bin" --dump-kicks="$OUT/kicks.bin" \
    > "$OUT/labels.txt" 2>&1 ;;
simulate)
  $J simulate --config=configs/right_foot_planner.textproto --controller=planner --seconds=8 \
    --envs=2 --threads=1 --planner-set="samples: 8 iterations: 2" > "$OUT/simulate.txt" 2>&1 ;;
train) train train configs/learning/guided_cheap_consistent.textproto ;;  # guided: cloning
ppo) train ppo configs/right_foot.textproto ;;                                # PPO's steps
guided_nopre) train guided_nopre configs/learning/guided_no_pretraining.textproto ;;
*) echo "unknown golden run '$w'" >&2; exit 2 ;;
esac; done
