#!/bin/bash
# Offline DAgger rounds with the planner as teacher (docs/learning.md, "Offline DAgger"): the
# student clones every demonstration buffer so far, then drives episodes itself while the
# planner labels every state it visits; the new labels join the data and the student is cloned
# again. Each round is evaluated alone on the held-out starts. Resumable: a round whose files
# exist is skipped, so re-running the same command continues.
#
#   scripts/experiments/dagger_offline.sh OUT CONFIG DEMOS ROUNDS [EPISODES] [SECONDS] [PLANNER_SET]
#   e.g. scripts/experiments/dagger_offline.sh runs/dagger configs/right_foot_planner.textproto \
#          runs/d0/a.jgld,runs/d0/b.jgld 3 24 6 'samples: 16 iterations: 3'
#
# DEMOS: the initial buffers (comma-separated, e.g. from `juggle label-spread --dump-demos`),
# whose observations are CONFIG's. Per round R: OUT/student_R.jglpolicy (cloned from all data so
# far), OUT/eval_R.log (20 held-out starts x 30 s), OUT/dagger_R.P.jgld (its states, labelled, one
# file per labelling process P).
# FIT_EPOCHS (default 30) and EVAL_EPISODES (default 20) override the fit and evaluation sizes.
# MIX: the student's share of the executed action per round, space-separated (DAgger's β
# schedule: the env executes label + β·(student − label); default "1", the last value repeats).
# LABEL_PROCS (default 1): labelling processes per round, one thread each, EPISODES apiece on
# their own starts.
set -euo pipefail
if [ $# -lt 4 ]; then
  sed -n '2,20p' "$0"
  exit 2
fi
out=$1; config=$2; demos=$3; rounds=$4; episodes=${5:-24}; seconds=${6:-6}; planner=${7:-}
epochs=${FIT_EPOCHS:-30}; eval_episodes=${EVAL_EPISODES:-20}
read -r -a mix <<< "${MIX:-1}"; procs=${LABEL_PROCS:-1}
juggle=${JUGGLE:-build/release/juggle}
[ -x "$juggle" ] || { echo "dagger_offline.sh: no juggle binary at $juggle (make build)" >&2; exit 1; }
mkdir -p "$out"
git rev-parse --short HEAD > "$out/COMMIT" 2>/dev/null || true

data=$demos
for ((r = 0; r <= rounds; r++)); do
  student="$out/student_$r.jglpolicy"
  if [ ! -s "$student" ]; then
    echo "== round $r: cloning $(echo "$data" | tr ',' '\n' | wc -l) buffers"
    "$juggle" fit-demos --demos="$data" --config="$config" --epochs="$epochs" \
      --json="$out/fit_$r.jsonl" --save-policy="$out/part_$r.jglpolicy" > "$out/fit_$r.log" 2>&1
    mv "$out/part_$r.jglpolicy" "$student"
    tail -n 2 "$out/fit_$r.log"
  fi
  if [ ! -s "$out/eval_$r.log" ] || ! grep -q 'median_juggles=' "$out/eval_$r.log"; then
    "$juggle" eval --policy="$student" --config="$config" --episodes="$eval_episodes" \
      --max_seconds=30 --json="$out/eval_$r.jsonl" > "$out/eval_$r.log.part" 2>&1
    mv "$out/eval_$r.log.part" "$out/eval_$r.log"
  fi
  echo "round $r student: $(grep -o -E '(median|p10|p90|mean)_juggles=[0-9.]+|mean_episode_s=[0-9.]+' "$out/eval_$r.log" | tr '\n' ' ')"
  [ "$r" -lt "$rounds" ] || break
  if [ ! -e "$out/dagger_$r.done" ]; then
    # The student drives (student_mix β of its deviation from the label); the planner labels
    # every state visited. Process p's starts are streams (1000·(p+1) + R, 0, e): training
    # starts, not the held-out ones.
    beta=${mix[$((r < ${#mix[@]} ? r : ${#mix[@]} - 1))]}
    pids=()
    for ((p = 0; p < procs; p++)); do
      "$juggle" label-spread --config="$config" --student="$student" --student-mix="$beta" \
        --episodes="$episodes" --seconds="$seconds" --forks=0 --seed=$((1000 * (p + 1) + r)) \
        --planner-set="threads: 1 $planner" --dump-demos="$out/dagger_$r.$p.jgld.part" \
        > "$out/label_$r.$p.log" 2>&1 &
      pids+=($!)
    done
    for pid in "${pids[@]}"; do wait "$pid"; done
    for ((p = 0; p < procs; p++)); do mv "$out/dagger_$r.$p.jgld.part" "$out/dagger_$r.$p.jgld"; done
    echo "student_mix $beta" > "$out/dagger_$r.done"
  fi
  # The round's buffers, however many processes made them.
  for f in "$out"/dagger_$r.*.jgld; do
    tail -n 2 "$out/label_$r.$(basename "$f" .jgld | cut -d. -f2).log"
    data="$data,$f"
  done
done
