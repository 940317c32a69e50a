#!/usr/bin/env bash
# Builds the learner and worker images from the built binaries (make build first):
#   juggle-learner:latest  juggle + configs + policies + libtorch's runtime
#   juggle-worker:latest   juggle-worker only (no libtorch)
# on the local Debian 12 base image (made here when missing). Layers with the Debian packages
# are cached by podman between builds; only the binaries' layers change.
#   deploy/images/build_images.sh [BUILD_DIR]      (default build/release)
set -euo pipefail
REPO=$(cd "$(dirname "$0")/../.." && pwd)
BUILD_DIR=$(cd "${1:-$REPO/build/release}" && pwd)
export CONTAINERS_CONF=${CONTAINERS_CONF:-$REPO/deploy/podman/containers.conf}
for binary in juggle juggle-worker; do
  [ -x "$BUILD_DIR/$binary" ] || { echo "error: $BUILD_DIR/$binary is missing (make build)" >&2; exit 1; }
done
"$REPO/deploy/images/make_base_image.sh"

CONTEXT=$(mktemp -d /var/tmp/juggle-images.XXXXXX)
trap 'rm -rf "$CONTEXT"' EXIT
cp "$BUILD_DIR/juggle" "$BUILD_DIR/juggle-worker" "$CONTEXT/"
strip "$CONTEXT/juggle" "$CONTEXT/juggle-worker"
cp -r "$REPO/configs" "$REPO/policies" "$CONTEXT/"

for image in worker learner; do
  echo "building juggle-$image:latest ..."
  podman build --network=host --quiet -f "$REPO/deploy/images/Containerfile.$image" \
    -t "juggle-$image:latest" "$CONTEXT" >/dev/null
  size=$(podman image inspect --format '{{.Size}}' "juggle-$image:latest")
  echo "juggle-$image:latest $((size / 1000000)) MB"
done
