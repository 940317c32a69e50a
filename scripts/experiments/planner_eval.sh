#!/bin/bash
# A long planner evaluation in parts that can stop and go on: episodes 0..EPISODES-1 (or those
# listed, e.g. 0,4,7) of `juggle eval --controller=planner` (the held-out streams of the
# default seed), one episode per part, SLOTS parts side by side with one planner thread each. A part whose JSON
# holds its episode line is done and skipped, so re-running the same command continues an
# interrupted evaluation. At the end the parts are summarized (scripts/analysis/eval_parts.py).
#
#   scripts/experiments/planner_eval.sh OUT CONFIG EPISODES SECONDS [SLOTS] [PLANNER_SET]
#   e.g. scripts/experiments/planner_eval.sh runs/planner_eval60 \
#          configs/right_foot_planner.textproto 20 60 2
#
# Every part also records its episode (OUT/ep_N.traj) for `juggle render --replay`.
# EVAL_FLAGS (environment): more `juggle eval` flags for every part, e.g.
# EVAL_FLAGS=--proposal=policies/right_foot/kick_fb_30min.jglpolicy; "{i}" in them becomes the
# part's episode index (e.g. --kick-memory-out=OUT/memory_{i}.txt).
set -euo pipefail
if [ $# -lt 4 ]; then
  sed -n '2,12p' "$0"
  exit 2
fi
out=$1; config=$2; episodes=$3; seconds=$4; slots=${5:-2}; extra=${6:-}
juggle=${JUGGLE:-build/release/juggle}
here=$(cd "$(dirname "$0")" && pwd)
[ -x "$juggle" ] || { echo "planner_eval.sh: no juggle binary at $juggle (make build)" >&2; exit 1; }
mkdir -p "$out"

part() {
  local i=$1 json="$out/ep_$1.jsonl"
  local flags=${EVAL_FLAGS:-}
  flags=${flags//\{i\}/$i}
  if [ -s "$json" ] && grep -q '"table":"episode"' "$json"; then return 0; fi
  # --planner-stream-base=0: every part plans from stream 0, as the documented runs of this
  # protocol did (docs/performance.md), so they reproduce.
  "$juggle" eval --controller=planner --config="$config" --episodes=1 --first-episode="$i" \
    --planner-stream-base=0 --max_seconds="$seconds" --planner-set="threads: 1 $extra" --json="$json.part" \
    --record="$out/ep_$i.traj" $flags > "$out/ep_$i.log" 2>&1
  mv "$json.part" "$json"
  echo "episode $i: $(grep -o 'juggles=[0-9.]*' "$out/ep_$i.log" | head -1) $(tail -1 "$out/ep_$i.log" | grep -o 'wall_s=[0-9.]*')"
}

if [[ "$episodes" == *,* ]]; then
  IFS=, read -r -a list <<< "$episodes"
else
  list=($(seq 0 $((episodes - 1))))
fi
running=0
for i in "${list[@]}"; do
  part "$i" &
  running=$((running + 1))
  if [ "$running" -ge "$slots" ]; then wait -n; running=$((running - 1)); fi
done
wait
/usr/bin/python3 "$here/../analysis/eval_parts.py" "$out"/ep_*.jsonl
