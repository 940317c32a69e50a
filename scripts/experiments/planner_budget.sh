#!/bin/bash
# Juggles against the planner's budget (docs/planner.md, "Budget"): the same held-out starts
# evaluated once per setting with scripts/experiments/planner_eval.sh (resumable: a finished
# episode is skipped), then one table row per setting: median and mean juggles, the planner's
# rollout steps per simulated second (its budget, independent of what else runs), and
# core-seconds per simulated second (one planner thread per episode, SLOTS episodes side by
# side: wall seconds, so core-seconds only while SLOTS <= free cores and nothing else runs).
#
#   scripts/experiments/planner_budget.sh OUT CONFIG EPISODES SECONDS SLOTS LABEL=SETTINGS ...
#   e.g. scripts/experiments/planner_budget.sh runs/budget configs/right_foot_planner.textproto \
#          0,1,2,3,4,5,6,7 10 2 "s8x2=samples: 8 iterations: 2" "s32x5="
#
# LABEL names the setting's folder under OUT; SETTINGS (may be empty: the config as it is) is
# text-format PlannerConfig fields given to `juggle eval --planner-set`.
set -euo pipefail
if [ $# -lt 6 ]; then
  sed -n '2,12p' "$0"
  exit 2
fi
out=$1; config=$2; episodes=$3; seconds=$4; slots=$5
shift 5
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
rows=()
for setting in "$@"; do
  label=${setting%%=*}
  fields=${setting#*=}
  [ -n "$label" ] && [ "$label" != "$setting" ] || {
    echo "planner_budget.sh: '$setting' is not LABEL=SETTINGS" >&2; exit 2; }
  [[ "$fields" != *"|"* ]] || { echo "planner_budget.sh: '|' in '$setting'" >&2; exit 2; }
  shown=${fields:-"(as the config has them)"}
  echo "== $label: $shown"
  # Progress goes to the terminal and OUT/LABEL.log; the summary line is kept for the table.
  "$here/planner_eval.sh" "$out/$label" "$config" "$episodes" "$seconds" "$slots" "$fields" \
    | tee "$out/$label.log"
  summary=$(grep '^episodes=' "$out/$label.log" | tail -1)
  rows+=("$label|$fields|$summary")
done
echo
echo "| setting | planner settings | episodes | median | mean | rollout steps per sim-s | core-s per sim-s |"
echo "|---|---|---|---|---|---|---|"
for row in "${rows[@]}"; do
  IFS='|' read -r label fields summary <<< "$row"
  value() { grep -o "$1=[0-9.]*" <<< "$summary" | cut -d= -f2; }
  echo "| $label | ${fields:-—} | $(value episodes) | $(value median_juggles) |" \
       "$(value mean_juggles) | $(value rollout_steps_per_sim_s) | $(value core_s_per_sim_s) |"
done
