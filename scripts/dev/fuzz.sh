#!/usr/bin/env bash
# Runs the libFuzzer harnesses of tests/fuzz/ (docs/reliability.md).
#
#   scripts/dev/fuzz.sh [SECONDS_EACH] [NAME...]     (default 60 s, every harness; `make fuzz`)
#
# Builds the named harnesses (all six by default) of the `fuzz` preset (clang, ASan + UBSan)
# when needed, fuzzes each from its committed seed corpus (tests/fuzz/corpus/NAME, copied to
# build/fuzz/corpus/NAME so new inputs stay out of the tree) and stops at the first crash,
# leaking input or timeout, whose input is left in build/fuzz/crashes/NAME/. To keep a crash as
# a regression test: fix it, then copy the input to tests/fuzz/regressions/NAME/ (replayed by
# ctest, `make test`). `make test-fuzz` (run by .ci/run): 10 s each.
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then
  sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
fi
seconds=${1:-60}
shift || true
names=("$@")
[[ ${#names[@]} -gt 0 ]] || names=(fuzz_chunk fuzz_config fuzz_checkpoint fuzz_policy_file fuzz_policy_snapshot fuzz_siteswap)
command -v clang++ >/dev/null || { echo "error: clang++ not found (make deps installs it)" >&2; exit 1; }
[[ -f build/fuzz/build.ninja ]] || cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)" --target "${names[@]}"
status=0
for name in "${names[@]}"; do
  corpus=build/fuzz/corpus/$name crashes=build/fuzz/crashes/$name
  mkdir -p "$corpus" "$crashes"
  cp -n tests/fuzz/corpus/"$name"/* "$corpus"/ 2>/dev/null || true
  echo "== $name: ${seconds} s from $(ls "$corpus" | wc -l) inputs"
  # -rss_limit_mb: a harness that allocates what a peer claims shows up as an out-of-memory crash.
  if build/fuzz/fuzz/"$name" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
       -max_len=65536 -print_final_stats=1 -artifact_prefix="$crashes/" \
       >"build/fuzz/$name.log" 2>&1; then
    grep -E "^stat::number_of_executed_units|^stat::new_units_added" "build/fuzz/$name.log" | tr '\n' ' '
    echo "corpus now $(ls "$corpus" | wc -l) inputs: ok"
  else
    echo "$name FAILED: see build/fuzz/$name.log and $crashes/"; status=1
    grep -E "ERROR|SUMMARY" "build/fuzz/$name.log" | head -5
  fi
done
exit $status
