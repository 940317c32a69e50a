#!/usr/bin/env bash
# The toss-juggling recipe (docs/toss.md, docs/results.md): residual catch and throw policies on
# the base controllers, trained side by side inside the two-arm loop on every pattern and on
# transitions (configs/toss_residual_{catch,throw}.textproto); the throw checkpoints ranked with
# the last catch on held-out seeds 101-105, then the catch checkpoints with the best throw; the
# exported pair and the evaluation protocol on seeds 1001-1010.
#
#   scripts/experiments/train_toss.sh [RUNS_DIR] [ITERATIONS]   (default runs 6000; make train-toss)
#
# Every stage stops at a fixed iteration, so the result does not depend on how busy the machine
# is; a stage already at its iteration is skipped, a stopped one resumes. About 30 min on 2
# cores. Writes RUNS_DIR/toss_pair/{catch,throw}.jglpolicy, eval.txt and eval.jsonl.
# The earlier recipe (policies alone, no base controllers): train_toss_from_scratch.sh.
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then
  sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
fi
runs=${1:-runs}
iterations=${2:-6000}
juggle=${JUGGLE:-build/release/juggle}
[[ -x $juggle ]] || { echo "error: $juggle not built (make build)" >&2; exit 1; }
pair=$runs/toss_pair
mkdir -p "$runs" "$pair"

stage() {  # stage NAME CONFIG: trains unless already at $iterations
  local name=$1 config=$2 dir=$runs/$1
  if [[ -f $dir/checkpoints/$(printf 'ckpt-%010d.jglc' "$iterations") ]]; then
    echo "[$(date +%T)] $name: already at iteration $iterations"
    return 0
  fi
  local args=(train --config="$config" --run_dir="$dir" --iterations="$iterations"
              --metrics_port=0)
  if compgen -G "$dir/checkpoints/*.jglc" >/dev/null; then args+=(--resume); fi
  echo "[$(date +%T)] $name: ${args[*]}"
  "$juggle" "${args[@]}" >"$dir.log" 2>&1 || { echo "error: $name failed, see $dir.log" >&2; return 1; }
  echo "[$(date +%T)] $name: done ($(tail -n 1 "$dir.log"))"
}

rank() {  # rank ROLE RUN PARTNER: prints the best checkpoint of RUN (ranking in RUN/ranking.txt)
  local role=$1 run=$2 partner=$3 dir=$2/rank
  rm -rf "$dir" && mkdir -p "$dir/a" "$dir/b"
  local half=a
  for ckpt in "$run"/checkpoints/*.jglc; do
    ln -s "$(realpath "$ckpt")" "$dir/$half/"
    if [[ $half == a ]]; then half=b; else half=a; fi
  done
  for half in a b; do
    WIND_MAX=1.0 JUGGLE=$juggle scripts/experiments/rank_toss_checkpoints.sh "$role" "$dir/$half" \
      "$partner" 3,4,5,6,7,53,441,531 >"$dir/$half.txt" &
  done
  wait
  sort -k1,1n -k2,2n -k3,3nr "$dir/a.txt" "$dir/b.txt" >"$run/ranking.txt"
  realpath "$(tail -n 1 "$run/ranking.txt" | cut -d' ' -f4)"
}

stage toss_residual_throw configs/toss_residual_throw.textproto & t=$!
stage toss_residual_catch configs/toss_residual_catch.textproto & c=$!
wait $t && wait $c

echo "[$(date +%T)] ranking the throw checkpoints with the last catch (seeds 101-105)"
best_throw=$(rank throw "$runs/toss_residual_throw" "$runs/toss_residual_catch")
echo "[$(date +%T)] best throw: $best_throw; ranking the catch checkpoints with it"
best_catch=$(rank catch "$runs/toss_residual_catch" "$best_throw")
echo "[$(date +%T)] best catch: $best_catch"
"$juggle" export-policy --checkpoint="$best_throw" --out="$pair/throw.jglpolicy" | tail -n 1
"$juggle" export-policy --checkpoint="$best_catch" --out="$pair/catch.jglpolicy" | tail -n 1
printf '%s\n%s\n' "$best_catch" "$best_throw" >"$pair/sources.txt"
"$juggle" toss --eval --catch="$pair/catch.jglpolicy" --throw="$pair/throw.jglpolicy" \
  --json="$pair/eval.jsonl" | tee "$pair/eval.txt"
