#!/usr/bin/env bash
# The ablation study (paper Fig. 7-8; docs/results.md, "Ablations"): trains every ablation
# config for the same number of iterations (= the same samples: every config has the same
# envs and unroll length) on each seed, one run after another with the whole machine,
# evaluates each final policy (`juggle eval --json`), and plots the learning curves averaged
# over seeds (scripts/analysis/plot_ablation.py). Runs land in OUT_DIR/<config>_s<seed>/.
#
# usage: scripts/experiments/ablation.sh OUT_DIR ITERATIONS "SEED..." [CONFIG...]
#   default configs: configs/ablation/{layerwise_moe,output_moe,mlp,uniform_walk}.textproto
#   JUGGLE=build/juggle EPISODES=20 scripts/experiments/ablation.sh runs/ablation 2000 "1 2 3"
set -euo pipefail
[ $# -ge 3 ] || { sed -n '2,10p' "$0"; exit 2; }
out=$1 iterations=$2 seeds=$3
shift 3
here=$(cd "$(dirname "$0")" && pwd)
configs=("$@")
if [ ${#configs[@]} -eq 0 ]; then
  configs=()
  for name in layerwise_moe output_moe mlp uniform_walk; do
    configs+=("$here/../../configs/ablation/$name.textproto")
  done
fi
juggle=${JUGGLE:-build/release/juggle}
episodes=${EPISODES:-20}
[ -x "$juggle" ] || { echo "ablation: no juggle binary at $juggle (set JUGGLE=...)" >&2; exit 1; }
mkdir -p "$out"
summary="$out/summary.tsv"
printf 'config\tseed\titerations\tmedian_juggles\tmean_juggles\tmean_completions\n' > "$summary"
value() { echo "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"; }

for seed in $seeds; do
  for config in "${configs[@]}"; do
    name=$(basename "$config" .textproto)
    dir="$out/${name}_s$seed"
    rm -rf "$dir"
    echo "ablation: $name seed $seed, $iterations iterations -> $dir"
    "$juggle" train --config="$config" --seed="$seed" --run_dir="$dir" \
        --iterations="$iterations" > "$out/${name}_s$seed.log" 2>&1
    line=$("$juggle" eval --policy="$dir" --episodes="$episodes" --max_seconds=30 \
        --json="$dir/final_eval.jsonl" | tail -n 1)
    echo "$line" > "$dir/final_eval.txt"
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$seed" "$iterations" \
        "$(value "$line" median_juggles)" "$(value "$line" mean_juggles)" \
        "$(value "$line" mean_completions)" | tee -a "$summary"
  done
done
/usr/bin/python3 "$here/../analysis/plot_ablation.py" "$out" "$out/ablation.svg"
