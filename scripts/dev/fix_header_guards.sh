#!/usr/bin/env bash
# Rewrites the include guard of each given header to JUGGLE_<PATH>_H_ (path from the repo root).
set -euo pipefail
cd "$(dirname "$0")/../.."
for f in "$@"; do
  guard="JUGGLE_$(echo "${f%.h}" | tr '/a-z.-' '_A-Z__')_H_"
  old=$(grep -m1 -oP '^#ifndef \K\w+' "$f" || true)
  [ -z "$old" ] || [ "$old" = "$guard" ] && continue
  sed -i "s/\b$old\b/$guard/g" "$f"
done
