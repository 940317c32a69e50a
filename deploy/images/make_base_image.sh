#!/usr/bin/env bash
# Makes the Debian 12 base image (juggle-base:bookworm) locally: no registry is needed, only the
# Debian archive apt already uses. debootstrap (minbase) into a scratch folder, then podman import.
# Skips the work when the image exists (FORCE=1 rebuilds it).
#   deploy/images/make_base_image.sh [MIRROR]
set -euo pipefail
IMAGE=${BASE_IMAGE:-juggle-base:bookworm}
MIRROR=${1:-$(sed -n 's/^URIs: *//p' /etc/apt/sources.list.d/debian.sources 2>/dev/null | head -n 1)}
MIRROR=${MIRROR:-http://deb.debian.org/debian}
export CONTAINERS_CONF=${CONTAINERS_CONF:-$(cd "$(dirname "$0")/.." && pwd)/podman/containers.conf}

if [ "${FORCE:-0}" != 1 ] && podman image exists "$IMAGE"; then
  echo "base image $IMAGE exists (FORCE=1 rebuilds it)"
  exit 0
fi
for tool in debootstrap podman; do
  command -v "$tool" >/dev/null || { echo "error: $tool is missing (scripts/dev/install_deps.sh --deploy)" >&2; exit 1; }
done

ROOT=$(mktemp -d /var/tmp/juggle-base.XXXXXX)
trap 'rm -rf "$ROOT"' EXIT
echo "debootstrap bookworm (minbase) from $MIRROR ..."
debootstrap --variant=minbase bookworm "$ROOT" "$MIRROR" > "$ROOT.log" 2>&1 || {
  tail -n 20 "$ROOT.log" >&2; echo "error: debootstrap failed (log: $ROOT.log)" >&2; exit 1; }
rm -f "$ROOT.log"
# The image's apt uses the same archive; no caches or docs ship in it.
echo "deb $MIRROR bookworm main" > "$ROOT/etc/apt/sources.list"
rm -rf "$ROOT"/var/cache/apt/archives/*.deb "$ROOT"/var/lib/apt/lists/* "$ROOT"/usr/share/doc/* \
       "$ROOT"/usr/share/man/*
tar -C "$ROOT" -c . | podman import --change 'CMD ["/bin/bash"]' - "$IMAGE" >/dev/null
echo "made $IMAGE ($(podman image inspect --format '{{.Size}}' "$IMAGE") bytes)"
