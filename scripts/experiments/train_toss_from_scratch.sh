#!/usr/bin/env bash
# The toss-juggling recipe (docs/toss.md, docs/results.md): the single-arm catch and throw
# policies, two rounds of training inside the two-arm loop, a held-out ranking of the round-2
# catch checkpoints, the exported pair and the evaluation on seeds 1-10.
#
#   scripts/experiments/train_toss_from_scratch.sh [RUNS_DIR]   (default runs; the recipe before the
#   base controllers: `make train-toss` now runs scripts/experiments/train_toss.sh)
#
# Every stage stops at a fixed iteration (the counts of the measured runs), so the result does
# not depend on how busy the machine is. Each stage trains on one core (the configs set one
# simulation and one torch thread); independent stages run side by side. About 2 h on 2 cores.
# Writes RUNS_DIR/toss_pair/{catch,throw}.jglpolicy and RUNS_DIR/toss_pair/eval.txt.
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then
  sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
fi
runs=${1:-runs}
juggle=${JUGGLE:-build/release/juggle}
partners=runs/toss_partners  # the loop configs name their frozen partners by this path
[[ -x $juggle ]] || { echo "error: $juggle not built (make build)" >&2; exit 1; }
mkdir -p "$runs" "$partners" "$runs/toss_pair"

stage() {  # stage NAME CONFIG ITERATIONS [INIT_FROM]: trains unless already at ITERATIONS
  local name=$1 config=$2 iterations=$3 init=${4:-} dir=$runs/$1
  if [[ -f $dir/checkpoints/$(printf 'ckpt-%010d.jglc' "$iterations") ]]; then
    echo "[$(date +%T)] $name: already at iteration $iterations"
    return 0
  fi
  local args=(train --config="$config" --run_dir="$dir" --iterations="$iterations"
              --metrics_port=0)
  if compgen -G "$dir/checkpoints/*.jglc" >/dev/null; then args+=(--resume)
  elif [[ -n $init ]]; then args+=(--init_from="$init"); fi
  echo "[$(date +%T)] $name: ${args[*]}"
  "$juggle" "${args[@]}" >"$dir.log" 2>&1 || { echo "error: $name failed, see $dir.log" >&2; return 1; }
  echo "[$(date +%T)] $name: done ($(tail -n 1 "$dir.log"))"
}
export_policy() {  # export_policy CHECKPOINT OUT [CONFIG]
  "$juggle" export-policy --checkpoint="$1" --out="$2" ${3:+--config="$3"} | tail -n 1
}

# Single-arm tasks, side by side.
stage toss_catch configs/toss_catch.textproto 2500 & catch_pid=$!
stage toss_throw configs/toss_throw.textproto 8020 & throw_pid=$!
wait $catch_pid && wait $throw_pid
export_policy "$runs/toss_catch" "$partners/catch_r0.jglpolicy"
export_policy "$runs/toss_throw" "$partners/throw_r0.jglpolicy"

# Round 1: each policy fine-tuned in the loop against both single-arm partners, side by side.
stage toss_loop1_throw configs/toss_loop1_throw.textproto 12011 "$runs/toss_throw" & t1=$!
stage toss_loop1_catch configs/toss_loop1_catch.textproto 4802 "$runs/toss_catch" & c1=$!
wait $t1 && wait $c1
export_policy "$runs/toss_loop1_throw" "$partners/throw_r1.jglpolicy"

# Round 2: the catch against the round-1 throw it will meet.
stage toss_loop2_catch configs/toss_loop2_catch.textproto 6585 "$runs/toss_loop1_catch"

# Held-out choice of the round-2 checkpoint (seeds 101-105), then the pair and its table. The
# checkpoints are ranked in two halves side by side.
echo "[$(date +%T)] ranking round-2 catch checkpoints on seeds 101-105"
rank_dir=$runs/toss_loop2_catch/rank
rm -rf "$rank_dir" && mkdir -p "$rank_dir/a" "$rank_dir/b"
half=a
for ckpt in "$runs"/toss_loop2_catch/checkpoints/*.jglc; do
  ln -s "$(realpath "$ckpt")" "$rank_dir/$half/"
  if [[ $half == a ]]; then half=b; else half=a; fi
done
for half in a b; do
  JUGGLE=$juggle scripts/experiments/rank_toss_checkpoints.sh catch "$rank_dir/$half" \
    "$runs/toss_loop1_throw" 3,4,5,531,53,441,6,7 >"$rank_dir/$half.txt" &
done
wait
sort -k1,1n -k2,2n -k3,3nr "$rank_dir/a.txt" "$rank_dir/b.txt" | tee "$runs/toss_loop2_catch/ranking.txt"
best=$(realpath "$(tail -n 1 "$runs/toss_loop2_catch/ranking.txt" | cut -d' ' -f4)")
# The pair carries the single-arm task configs: the same world as the loop configs, without the
# loop's inlined partner policies (which would make each file several MB).
export_policy "$best" "$runs/toss_pair/catch.jglpolicy" configs/toss_catch.textproto
export_policy "$runs/toss_loop1_throw" "$runs/toss_pair/throw.jglpolicy" configs/toss_throw.textproto
echo "$best" >"$runs/toss_pair/catch_source.txt"
"$juggle" toss --eval --catch="$runs/toss_pair/catch.jglpolicy" \
  --throw="$runs/toss_pair/throw.jglpolicy" | tee "$runs/toss_pair/eval.txt"
