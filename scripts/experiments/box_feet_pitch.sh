#!/bin/bash
# The football pitch with DeepMimic's box feet instead of the boots (seed 002's ablation; issue
# 45): writes OUT/models/ (the pitch with juggle_scene.xml's foot and sole classes — the box
# meets the ball and the turf —, and the files it includes) and, for each CONFIG given,
# OUT/<its name>: the shipped config with only the model file changed; prints their paths.
#
#   scripts/experiments/box_feet_pitch.sh OUT [CONFIG ...]
#   e.g. scripts/experiments/box_feet_pitch.sh /tmp/box configs/football_kick.textproto
#        build/release/juggle eval --controller=planner --config=/tmp/box/football_kick.textproto ...
set -euo pipefail
if [ $# -lt 1 ]; then
  sed -n '2,9p' "$0"
  exit 2
fi
out=$1; shift
repo=$(cd "$(dirname "$0")/../.." && pwd)
models=$repo/configs/models
mkdir -p "$out/models"
cp "$models/humanoid.xml" "$models/football_ball.xml" "$out/models/"
# The span of the foot and sole classes, from `<default class="foot">` to the sole's `</default>`.
classes() {
  awk '/<default class="foot">/ {on = 1} on {print} on && /<\/default>/ && seen {exit} /<default class="sole">/ {seen = 1}' "$1"
}
box=$(classes "$models/juggle_scene.xml")
boot=$(classes "$models/football_pitch.xml")
[ -n "$box" ] && [ -n "$boot" ] && grep -q 'mesh="boot"' <<< "$boot" ||
  { echo "box_feet_pitch.sh: no foot and sole classes in $models/juggle_scene.xml and football_pitch.xml" >&2; exit 1; }
BOX="$box" BOOT="$boot" /usr/bin/python3 -c '
import os, sys
text = open(sys.argv[1]).read()
assert os.environ["BOOT"] in text
sys.stdout.write(text.replace(os.environ["BOOT"], os.environ["BOX"]))' \
  "$models/football_pitch.xml" > "$out/models/football_pitch.xml"
echo "$out/models/football_pitch.xml"
for config in "$@"; do
  name=$(basename "$config")
  printf 'base_config: "%s"\nfootball { model_file: "models/football_pitch.xml" }\n' \
    "$(cd "$(dirname "$config")" && pwd)/$name" > "$out/$name"
  echo "$out/$name"
done
