#!/usr/bin/env bash
# The service's tests under sanitizers (docs/reliability.md), `make test-sanitize`:
#   ASan + UBSan (preset asan): learner, protocol, security, multi-process, assembly, parsing;
#   TSan (preset tsan): the threaded ones — protocol, asynchronous mode, queue, env pool.
#
#   scripts/dev/test_sanitize.sh [asan|tsan|all]      (default all)
#
# System libraries (libtorch, gRPC, protobuf, OpenMP) are not instrumented; the suppressions in
# tests/sanitizers/ name each library that needs one and why. Ends with ctest's summary.
set -euo pipefail
if [[ ${1:-} == -h || ${1:-} == --help ]]; then
  sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
fi
which=${1:-all}
jobs=${JOBS:-$(nproc)}
root=$(pwd)
ASAN_TARGETS=(juggle service_test learner_start_test multiprocess_test learner_test learner_core_test
  common_test)
ASAN_SUITES='RolloutProtocolTest|SecureServiceTest|TransportSecurityTest|AsyncModeTest|LearnerStartTest|MultiProcessTest|ContributionAssemblerTest|WorkerRegistryTest|SyncRoundTest|CheckpointTest|CheckpointParseTest|ChunkCodecTest|PolicyStoreTest'
TSAN_TARGETS=(service_test common_test env_pool_test learner_test learner_core_test planner_test)
TSAN_SUITES='RolloutProtocolTest|AsyncModeTest|BoundedQueueTest|EnvPoolTest|PolicyStoreTest|ForkJoinPoolTest|RecedingHorizonTest|PlanningModelTest'
status=0
run() {  # run PRESET SUITES EXCLUDE TARGETS...
  local preset=$1 suites=$2 exclude=$3; shift 3
  [[ -f build/$preset/build.ninja ]] || cmake --preset "$preset" >/dev/null
  cmake --build "build/$preset" -j "$jobs" --target "$@"
  (cd "build/$preset" && ctest -R "^($suites)\." -E "$exclude" -j "$jobs" --output-on-failure) || status=1
}
if [[ $which == asan || $which == all ]]; then
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_odr_violation=0"
  export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$root/tests/sanitizers/ubsan.supp"
  run asan "$ASAN_SUITES" '^$' "${ASAN_TARGETS[@]}"
fi
if [[ $which == tsan || $which == all ]]; then
  export TSAN_OPTIONS="suppressions=$root/tests/sanitizers/tsan.supp:halt_on_error=1:second_deadlock_stack=1:ignore_noninstrumented_modules=1"
  # The gRPC health-service test exercises only gRPC's callback server (no juggle code), whose
  # objects cross threads inside uninstrumented libgrpc++: not meaningful under TSan here.
  run tsan "$TSAN_SUITES" 'HealthServiceReportsServing' "${TSAN_TARGETS[@]}"
fi
exit $status
