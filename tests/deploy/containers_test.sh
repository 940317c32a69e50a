#!/usr/bin/env bash
# The images train together: builds juggle-learner and juggle-worker (deploy/images/), runs one
# learner container and two worker containers (podman, runc, host network so everything stays
# on loopback) with a token and TLS, and checks that both workers register, iterations advance
# and the gRPC health probe passes from both images. Prints both image sizes.
#   tests/deploy/containers_test.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/lib.sh"
need podman debootstrap openssl curl
BUILD_DIR=$(cd "${1:-$REPO/build/release}" && pwd)
"$REPO/deploy/images/build_images.sh" "$BUILD_DIR"

TMP=$(mktemp -d /var/tmp/juggle-containers.XXXXXX)
NAME=juggle-ct-$$
cleanup() {
  podman rm -f -t 2 "$NAME-learner" "$NAME-worker1" "$NAME-worker2" >/dev/null 2>&1 || true
  rm -rf "$TMP"
}
trap cleanup EXIT
make_secrets "$TMP/secrets" localhost 127.0.0.1
chmod 644 "$TMP"/secrets/*  # the containers' root reads them through the bind mount
mkdir -p "$TMP/runs"
PORT=$(free_port); METRICS=$(free_port)
SECRETS="-v $TMP/secrets:/etc/juggle:ro"

log "learner container (configs/right_foot.textproto, gRPC :$PORT, metrics :$METRICS)"
podman run -d --name "$NAME-learner" --network=host $SECRETS -v "$TMP/runs:/runs" \
  juggle-learner:latest learner --config=configs/right_foot.textproto --port="$PORT" \
  --metrics_port="$METRICS" --run_dir=/runs/containers --token_file=/etc/juggle/token \
  --tls_cert=/etc/juggle/learner.pem --tls_key=/etc/juggle/learner.key >/dev/null
for i in 1 2; do
  podman run -d --name "$NAME-worker$i" --network=host $SECRETS juggle-worker:latest \
    --learner="localhost:$PORT" --envs=2 --threads=1 --token_file=/etc/juggle/token \
    --tls_ca=/etc/juggle/ca.pem >/dev/null
done
show_logs() { for c in learner worker1 worker2; do echo "--- $c"; podman logs --tail 15 "$NAME-$c" 2>&1; done; }

probe() { podman exec "$NAME-learner" juggle worker --probe --learner="localhost:$PORT" --tls_ca=/etc/juggle/ca.pem; }
wait_for 60 "the learner's gRPC health probe passes (juggle worker --probe, TLS)" probe || { show_logs; die "probe"; }
podman run --rm --network=host $SECRETS juggle-worker:latest --probe --learner="localhost:$PORT" \
  --tls_ca=/etc/juggle/ca.pem || die "juggle-worker --probe from the worker image"
if podman run --rm --network=host juggle-worker:latest --probe --learner="localhost:$PORT" >/dev/null 2>&1; then
  die "a plaintext probe of the TLS port passed"
fi
wait_for 90 "2 workers registered" metric_at_least "$METRICS" juggle_workers_connected 2 || { show_logs; die "workers"; }
wait_for 180 "policy version >= 3: the containers train together" \
  metric_at_least "$METRICS" juggle_policy_version 3 || { show_logs; die "no iterations"; }
log "learner: version $(metric "$METRICS" juggle_policy_version), workers $(metric "$METRICS" juggle_workers_connected), samples $(metric "$METRICS" juggle_samples_total)"
[ -f "$TMP/runs/containers/metrics.jsonl" ] || die "no metrics.jsonl in the learner's volume"

for image in learner worker; do
  size=$(podman image inspect --format '{{.Size}}' "juggle-$image:latest")
  echo "image juggle-$image:latest: $((size / 1000000)) MB"
done
log "PASS"
