#!/usr/bin/env bash
# Ranks the checkpoints of one toss policy by pattern juggling with a fixed partner, on held-out
# seeds (101..105 by default; `juggle toss --eval` reports on seeds 1..10). Checkpoints of one
# run differ a lot (docs/results.md), so a run's last checkpoint is not necessarily its best.
#
#   scripts/experiments/rank_toss_checkpoints.sh catch DIR PARTNER_THROW [PATTERNS] [FIRST_SEED]
#   scripts/experiments/rank_toss_checkpoints.sh throw DIR PARTNER_CATCH [PATTERNS] [FIRST_SEED]
# (WIND_MAX=0.3: the largest wind of the sweep, N; 0 skips it)
#
# DIR holds .jglc files; PARTNER is a checkpoint file or run directory. Prints one line per
# checkpoint, best last: score (sum over the patterns of the median throws, capped at 200),
# the largest wind (N) under which 3 still reaches 100 throws (the first tie-breaker), the mean
# over the patterns of their mean release-velocity error (m/s, the second: lower is better),
# checkpoint, medians.
set -euo pipefail
if [[ $# -lt 3 || ( $1 != catch && $1 != throw ) ]]; then
  sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
role=$1 dir=$2 partner=$3 patterns=${4:-3,4,5,531} first_seed=${5:-101}
juggle=${JUGGLE:-build/release/juggle}
shopt -s nullglob
files=("$dir"/*.jglc)
if [[ ${#files[@]} -eq 0 ]]; then
  echo "error: no checkpoints (*.jglc) in $dir" >&2
  exit 1
fi
for ckpt in "${files[@]}"; do
  if [[ $role == catch ]]; then pair=(--catch="$ckpt" --throw="$partner")
  else pair=(--catch="$partner" --throw="$ckpt"); fi
  out=$("$juggle" toss --eval "${pair[@]}" --patterns="$patterns" --seeds=5 \
        --seed="$first_seed" --wind-max="${WIND_MAX:-0.3}" --transitions=none)
  line=$(tail -n 1 <<<"$out")
  # Pattern rows: pattern balls median v_err v_max z_cm per-seed...
  verr=$(awk -v p="$patterns" 'BEGIN {n = split(p, a, ","); for (i = 1; i <= n; ++i) want[a[i]] = 1}
         ($1 in want) && NF > 6 {s += $4; ++k} END {printf "%.5f", k ? s / k : 0}' <<<"$out")
  medians=$(grep -o 'throws_[0-9a-z]*=[0-9]*' <<<"$line" | tr '\n' ' ')
  score=$(grep -o 'throws_[0-9a-z]*=[0-9]*' <<<"$line" | cut -d= -f2 | awk '{s += ($1 > 200 ? 200 : $1)} END {print s}')
  wind=$(grep -o 'max_wind_n=[0-9.]*' <<<"$line" | cut -d= -f2)
  echo "$score $wind $verr $ckpt $medians"
done | sort -k1,1n -k2,2n -k3,3nr
