#!/usr/bin/env bash
# juggle-worker must not link libtorch or GL: cluster jobs run hundreds of them, and the worker
# image carries neither. Checks the binary's dynamic dependencies with ldd, and that it runs
# (--help). Usage: tests/worker_binary_test.sh BUILD_DIR
set -uo pipefail
bin="$1/juggle-worker"
[ -x "$bin" ] || { echo "no $bin"; exit 1; }
deps=$(ldd "$bin") || { echo "ldd failed on $bin"; exit 1; }
forbidden=$(echo "$deps" | grep -E 'libtorch|libc10|libgomp|libopenblas|libEGL|libGL|libOpenGL|libGLX' || true)
if [ -n "$forbidden" ]; then
  echo "juggle-worker links forbidden libraries:"
  echo "$forbidden"
  exit 1
fi
"$bin" --help > /dev/null || { echo "juggle-worker --help failed"; exit 1; }
echo "juggle-worker: $(echo "$deps" | wc -l) shared libraries, none of libtorch/GL; $(du -h "$bin" | cut -f1)"
# The full binary does link torch: the check would notice if the worker did.
echo "$(ldd "$1/juggle" | grep -c -E 'libtorch|libc10') torch libraries in juggle (expected > 0)"
[ "$(ldd "$1/juggle" | grep -c -E 'libtorch|libc10')" -gt 0 ]
