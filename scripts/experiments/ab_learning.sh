#!/usr/bin/env bash
# Side-by-side learning comparison (docs/learning.md, "Protocol"): for each seed, trains every
# given config at the same time — each with one simulation and one torch thread, so two runs
# share the 2 cores evenly — for MINUTES of wall time, then evaluates every final policy with
# `juggle eval` (EPISODES episodes from held-out seeds, episodes up to 60 s) and appends a row
# per run to OUT_DIR/summary.tsv. Runs in OUT_DIR/<config name>_s<seed>/.
# Resumable: a run directory with a checkpoint continues (`juggle train --resume`) for what is
# left of MINUTES of its cumulative training time (metrics.jsonl's train_s); a run that has had
# its MINUTES is not trained again; one already evaluated (final_eval.txt) is not re-evaluated
# unless it trains further (a later call with more MINUTES).
#
# usage: scripts/experiments/ab_learning.sh OUT_DIR MINUTES "SEED..." CONFIG [CONFIG...]
#   EPISODES=50 JUGGLE=build/release/juggle scripts/experiments/ab_learning.sh runs/ab 30 "1 2 3" \
#       configs/learning/baseline.textproto configs/learning/base.textproto
set -euo pipefail
[ $# -ge 4 ] || { sed -n '2,11p' "$0"; exit 2; }
out=$1 minutes=$2 seeds=$3
shift 3
juggle=${JUGGLE:-build/release/juggle}
episodes=${EPISODES:-50}
mkdir -p "$out"
summary="$out/summary.tsv"
[ -f "$summary" ] || printf 'config\tseed\tminutes\titerations\tsamples\tmedian_juggles\tp10\tp90\tmean_juggles\tfrac_ge_10\tfrac_ge_20\tmean_episode_s\tendings\n' > "$summary"

value() { echo "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"; }

for seed in $seeds; do
  pids=()
  for config in "$@"; do
    name=$(basename "$config" .textproto)
    dir="$out/${name}_s$seed"
    resume=()
    left=$minutes
    if ls "$dir"/checkpoints/* > /dev/null 2>&1; then
      done_s=$(grep -o '"train_s": *[0-9.]*' "$dir/metrics.jsonl" | tail -n 1 | sed 's/.*: *//')
      left=$(awk -v m="$minutes" -v s="${done_s:-0}" 'BEGIN { l = m - s / 60; print (l > 0.5 ? l : 0) }')
      resume=(--resume)
    else
      rm -rf "$dir"
    fi
    [ "$left" = 0 ] && continue
    rm -f "$dir/final_eval.txt"  # its evaluation was of fewer minutes
    echo "$name seed $seed: training for $left of $minutes minutes ${resume[*]}"
    "$juggle" train --config="$config" --seed="$seed" --run_dir="$dir" --minutes="$left" \
        "${resume[@]}" --workers=1 --threads=1 >> "$out/${name}_s$seed.log" 2>&1 &
    pids+=($!)
  done
  for pid in "${pids[@]}"; do wait "$pid"; done
  for config in "$@"; do
    name=$(basename "$config" .textproto)
    dir="$out/${name}_s$seed"
    [ -s "$dir/final_eval.txt" ] && continue
    line=$("$juggle" eval --policy="$dir" --episodes="$episodes" --max_seconds=60 | tail -n 1)
    echo "$line" > "$dir/final_eval.txt"
    last=$(grep -v '"event"' "$dir/metrics.jsonl" | tail -n 1)
    iterations=$(echo "$last" | sed -n 's/.*"iteration": *\([0-9]*\).*/\1/p')
    samples=$(echo "$last" | sed -n 's/.*"samples": *\([0-9]*\).*/\1/p')
    endings=$(echo "$line" | tr ' ' '\n' | grep -E '^(ball_lost|fell|bad_contact|contact_timing|time_limit|diverged)=' | tr '\n' ' ')
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$seed" "$minutes" \
        "$iterations" "$samples" "$(value "$line" median_juggles)" "$(value "$line" p10_juggles)" \
        "$(value "$line" p90_juggles)" "$(value "$line" mean_juggles)" \
        "$(value "$line" frac_juggles_ge_10)" "$(value "$line" frac_juggles_ge_20)" \
        "$(value "$line" mean_episode_s)" "$endings" | tee -a "$summary"
  done
done
