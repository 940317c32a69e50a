#!/usr/bin/env bash
# The codemap's dependency rules (README "Codemap", docs/DESIGN.md), checked on every
# #include of the project's C++ files. Fails naming each file:line that crosses a forbidden
# boundary. Run from the repository root (ctest does).
#   tests/layering_test.sh            check the repository
#   tests/layering_test.sh --self-test   check that a tree with violations fails
set -uo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--self-test" ]; then
  tree=$(mktemp -d)
  mkdir -p "$tree/tests" "$tree/worker" "$tree/envs" "$tree/common"
  cp "$0" "$tree/tests/layering_test.sh"
  printf '#include "learner/learner_server.h"\n' > "$tree/worker/a.cc"
  printf '#include <torch/torch.h>\n' > "$tree/envs/b.cc"
  printf '#include "envs/env.h"\n#include <mujoco/mujoco.h>\n' > "$tree/common/c.h"
  printf '#include "common/rng.h"\n#include <mujoco/mujoco.h>\n' > "$tree/envs/ok.cc"
  printf '#include "nlohmann/json.hpp"\n' > "$tree/worker/d.cc"
  out=$(bash "$tree/tests/layering_test.sh" 2>&1); status=$?
  rm -rf "$tree"
  echo "$out"
  # Exactly the five planted violations, and a failing exit status.
  [ $status -ne 0 ] && [ "$(echo "$out" | grep -c 'must not')" -eq 5 ] || { echo "self-test FAILED"; exit 1; }
  echo "self-test passed"
  exit 0
fi

# Project folders each folder may include (besides itself), and the libraries it may use.
declare -A PROJECT=(
  [common]="proto"
  [record]="common proto"
  [envs]="record common proto"
  [worker]="envs record common proto"
  [eval]="envs record common proto"
  [planner]="eval envs record common proto"
  [learner]="eval envs record common proto"
  [render]="eval envs record common proto"
  [export]="envs record common proto"
  [play]="export planner eval envs record common proto"
  [bench]="worker learner play planner eval envs record common proto"
  [app]="worker learner render export play planner eval bench envs record common proto"
  [tests]="worker learner render export play planner eval envs record common proto"
)
# httplib: cpp-httplib, only common/http_server.cc (the one HTTP implementation; the learner and
# tests reach HTTP through common/http_server.h, and juggle-worker never links it); grpc, only
# common/transport_security and common/connection_settings (token and TLS credentials, keepalive
# and reconnect settings: their own library juggle_transport).
# json: nlohmann-json, the one JSON library, where JSON is written or read: envs (toss
# evaluation lines), eval (evaluation tables), learner (dashboard API), export (replay page),
# app, bench, tests; not common, record, worker or render (the run log is protobuf JSON).
declare -A LIBS=(
  [common]="httplib grpc"
  [record]="mujoco"
  [envs]="mujoco json"
  [worker]="mujoco grpc"
  [eval]="mujoco json"
  [planner]="mujoco"
  [learner]="mujoco grpc torch json"
  [render]="mujoco gl"
  [export]="mujoco json"
  [play]="mujoco json"
  [bench]="mujoco grpc torch json"
  [app]="mujoco grpc torch gl json"
  [tests]="mujoco grpc torch json"
)

# The library an include belongs to, in `lib` ("" for the standard library, Abseil, Eigen,
# protobuf, gtest and other always-allowed headers). Sets a variable instead of printing: the
# loop below runs in this shell, without a subshell or a sed per #include (2,400 of them).
library_of() {
  case "$1" in
    mujoco/*) lib=mujoco ;;
    grpc/*|grpcpp/*|proto/rollout.grpc.pb.h) lib=grpc ;;
    torch/*|ATen/*|c10/*) lib=torch ;;
    EGL/*|GL/*|GLES*/*) lib=gl ;;
    httplib.h) lib=httplib ;;
    nlohmann/*) lib=json ;;
    *) lib="" ;;
  esac
}

violations=0
checked=0
include_re='^#include [<"]([^">]+)[">]'
for folder in "${!PROJECT[@]}"; do
  [ -d "$folder" ] || continue
  mapfile -t files < <(find "$folder" -name '*.h' -o -name '*.cc' | sort)
  [ ${#files[@]} -gt 0 ] || continue
  checked=$((checked + ${#files[@]}))
  # One grep for the folder: "file:line:#include ...", files in sorted order, lines ascending.
  while IFS=: read -r file line include; do
    if [[ $include =~ $include_re ]]; then target=${BASH_REMATCH[1]}; else target=$include; fi
    top=${target%%/*}
    if [ -n "${PROJECT[$top]+x}" ] && [ "$top" != "$folder" ]; then
      if ! [[ " ${PROJECT[$folder]} " == *" $top "* ]]; then
        echo "$file:$line: $folder/ must not include $top/ ($target)"
        violations=$((violations + 1))
      fi
    fi
    library_of "$target"
    if [ -n "$lib" ] && ! [[ " ${LIBS[$folder]} " == *" $lib "* ]]; then
      echo "$file:$line: $folder/ must not use $lib ($target)"
      violations=$((violations + 1))
    fi
  done < <(grep -H -n '^#include ' -- "${files[@]}")
done

# worker/ and learner/ never include each other (covered above); say what was checked.
echo "layering: $checked files checked, $violations violation(s)"
[ "$violations" -eq 0 ]
