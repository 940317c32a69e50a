#!/usr/bin/env bash
# Installs juggle's build and run dependencies from Debian packages when missing.
# Idempotent: does nothing (and needs no network) when everything is present.
#   scripts/dev/install_deps.sh            build, run and `make test`
#   scripts/dev/install_deps.sh --deploy   also `make test-deploy`'s engines (Slurm, podman, kubectl)
#   scripts/dev/install_deps.sh --netfaults  also `make test-netfaults`'s iproute2 and iptables
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config
  libmujoco-dev libqhull-dev
  libeigen3-dev libabsl-dev
  libprotobuf-dev protobuf-compiler
  libgrpc++-dev protobuf-compiler-grpc
  libtorch-dev libopenblas0-openmp
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev
  ffmpeg libegl-dev libopengl-dev libegl1 libegl-mesa0 libgl1-mesa-dri libpng-dev zlib1g-dev
  libjs-three chromium blender
  libcpp-httplib-dev nlohmann-json3-dev libjs-chart.js libjs-d3
  prometheus openssl clang libclang-rt-14-dev python3
)
# libcpp-httplib-dev: the learner's HTTP server; nlohmann-json3-dev: the dashboard's JSON API;
# libjs-chart.js, libjs-d3: the dashboard's charts and graph (embedded in the binary at build
# time); prometheus (prometheus + promtool) and chromium: tests of deploy/prometheus and of the
# dashboard in a real browser; openssl: certificates of the TLS tests; clang and
# libclang-rt-14-dev: the libFuzzer harnesses (scripts/dev/fuzz.sh); python3: the scripts/ tools
# (standard library only) and their tests.
if [ "${1:-}" = --deploy ]; then
  PACKAGES+=(slurmctld slurmd slurm-client munge podman runc catatonit debootstrap curl
             containernetworking-plugins iptables)
  # kubectl: any that has `kubectl kustomize`; Debian's kubernetes-client when there is none.
  command -v kubectl >/dev/null || PACKAGES+=(kubernetes-client)
fi
# Network-fault tests (docs/reliability.md): namespaces and veths (iproute2), partitions and
# packet loss as iptables rules.
if [ "${1:-}" = --netfaults ]; then
  PACKAGES+=(iproute2 iptables)
fi
# Deploy tests (docs/cluster.md): a single-node Slurm 22.05 (slurmctld, slurmd, munge), podman
# with runc (crun refuses this machine's hybrid cgroups) and catatonit (kube play's pause
# image), debootstrap for the local Debian base image, kubectl for `kubectl kustomize`.

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "install_deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
