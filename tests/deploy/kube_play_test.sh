#!/usr/bin/env bash
# deploy/k8s runs: `kubectl kustomize` renders the base and the podman overlay
# (tests/deploy/k8s-podman), and `podman kube play` runs the overlay against the images of
# deploy/images/: the learner's readiness probe (a gRPC health check over TLS) passes, the two
# worker replicas register, iterations advance, and `podman kube down` stops it all cleanly.
#   tests/deploy/kube_play_test.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/lib.sh"
need podman kubectl catatonit debootstrap openssl curl
BUILD_DIR=$(cd "${1:-$REPO/build/release}" && pwd)
PORT=50951 METRICS=9951   # fixed by the overlay
for p in $PORT $METRICS; do
  if curl -s --max-time 1 "http://127.0.0.1:$p/" >/dev/null 2>&1 || (echo > /dev/tcp/127.0.0.1/$p) 2>/dev/null; then
    die "port $p is in use; the podman overlay (tests/deploy/k8s-podman) needs it"
  fi
done
podman volume exists juggle-runs && die "a podman volume juggle-runs exists already; remove it first"

log "kubectl kustomize deploy/k8s"
kubectl kustomize "$REPO/deploy/k8s" > /dev/null || die "the base does not render"
"$REPO/deploy/images/build_images.sh" "$BUILD_DIR"

TMP=$(mktemp -d /var/tmp/juggle-kube.XXXXXX)
PLAYED=0
cleanup() {
  if [ "$PLAYED" = 1 ]; then podman kube down "$TMP/play.yaml" >/dev/null 2>&1 || true; fi
  podman volume rm -f juggle-runs >/dev/null 2>&1 || true
  rm -rf "$TMP"
}
trap cleanup EXIT
# The juggle-auth Secret's files (deploy/k8s/secret.example.yaml), in a host folder.
make_secrets "$TMP/made" juggle-learner 127.0.0.1
mkdir -p "$TMP/auth"
cp "$TMP/made/token" "$TMP/auth/token"; cp "$TMP/made/ca.pem" "$TMP/auth/ca.crt"
cp "$TMP/made/learner.pem" "$TMP/auth/tls.crt"; cp "$TMP/made/learner.key" "$TMP/auth/tls.key"
chmod 644 "$TMP"/auth/*
log "kubectl kustomize tests/deploy/k8s-podman"
kubectl kustomize "$REPO/tests/deploy/k8s-podman" | sed "s#KUBE_SECRETS_DIR#$TMP/auth#" > "$TMP/play.yaml"

LEARNER=juggle-learner-pod-0-learner
show_logs() {
  for c in $LEARNER juggle-worker-pod-0-worker juggle-worker-pod-1-worker; do
    echo "--- $c"; podman logs --tail 15 "$c" 2>&1 || true
  done
}
log "podman kube play"
podman kube play "$TMP/play.yaml" >/dev/null 2>"$TMP/play.err" || { cat "$TMP/play.err"; die "kube play"; }
PLAYED=1

# The readiness probe exactly as the manifest states it, run in the learner's container.
mapfile -t READY < <(/usr/bin/python3 - "$TMP/play.yaml" <<'PY'
import sys, yaml
for doc in yaml.safe_load_all(open(sys.argv[1])):
    if doc and doc["kind"] == "Deployment" and doc["metadata"]["name"] == "juggle-learner":
        print("\n".join(doc["spec"]["template"]["spec"]["containers"][0]["readinessProbe"]["exec"]["command"]))
PY
)
[ "${#READY[@]}" -gt 0 ] || die "no readiness probe in the rendered learner Deployment"
log "readiness probe: ${READY[*]}"
wait_for 60 "the learner's readiness probe passes" podman exec "$LEARNER" "${READY[@]}" \
  || { show_logs; die "readiness probe"; }
# podman runs the liveness probe (the same check) as the container's healthcheck.
status=$(podman healthcheck run "$LEARNER" 2>&1 || true)
[ -z "$status" ] || [ "$status" = healthy ] || { show_logs; die "liveness healthcheck: $status"; }
log "liveness healthcheck: healthy"

wait_for 90 "2 worker replicas registered" metric_at_least "$METRICS" juggle_workers_connected 2 \
  || { show_logs; die "workers"; }
wait_for 180 "policy version >= 3: the pods train together" \
  metric_at_least "$METRICS" juggle_policy_version 3 || { show_logs; die "no iterations"; }
log "learner: version $(metric "$METRICS" juggle_policy_version), workers $(metric "$METRICS" juggle_workers_connected)"
podman run --rm -v juggle-runs:/runs --entrypoint /bin/ls juggle-learner:latest /runs/right_foot/metrics.jsonl \
  >/dev/null || die "the learner did not write into the persistent volume"

# Kubernetes stops pods with SIGTERM: every process must exit cleanly (0) within the grace time.
for pod in juggle-worker-pod-0 juggle-worker-pod-1 juggle-learner-pod-0; do
  podman pod stop -t 30 "$pod" >/dev/null
done
for c in juggle-worker-pod-0-worker juggle-worker-pod-1-worker $LEARNER; do
  code=$(podman inspect --format '{{.State.ExitCode}}' "$c")
  [ "$code" = 0 ] || { show_logs; die "$c exited with $code on SIGTERM"; }
done
log "all three containers exited 0 on SIGTERM"
log "podman kube down"
podman kube down "$TMP/play.yaml" >/dev/null 2>"$TMP/down.err" || { cat "$TMP/down.err"; die "kube down"; }
PLAYED=0
for pod in juggle-learner-pod-0 juggle-worker-pod-0 juggle-worker-pod-1; do
  podman pod exists "$pod" && die "pod $pod is still there after kube down"
done
log "PASS"
