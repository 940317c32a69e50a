#!/usr/bin/env bash
# Network namespaces for the network-fault tests (docs/reliability.md, "Network faults"): one
# learner host and N worker hosts, each its own namespace, each worker joined to the learner
# by a veth pair (its own /30: learner side 10.213.K.1, worker side 10.213.K.2, addresses that
# exist only inside these namespaces). Faults are kernel rules: iptables DROP in one namespace's
# OUTPUT chain cuts one direction of one link silently (a partition, or half of one), an
# `statistic --mode random` DROP on the veths loses a share of the packets. Needs root.
#
#   netns.sh check                      exit 0 if this machine allows all of it, else 77 with
#                                       the reason on stderr (the ctest case then SKIPs)
#   netns.sh up PREFIX N                namespaces PREFIX-l, PREFIX-w0 .. PREFIX-w<N-1>
#   netns.sh down PREFIX N              removes them (and their veths)
#   netns.sh partition PREFIX K DIR     DIR: to_learner (the worker's packets are dropped),
#                                       to_worker (the learner's are), both
#   netns.sh heal PREFIX K              lifts worker K's partition
#   netns.sh loss PREFIX N PERCENT      drop PERCENT % of the packets arriving on every veth,
#                                       both sides (0: none)
set -uo pipefail

learner_ip() { echo "10.213.$1.1"; }
worker_ip() { echo "10.213.$1.2"; }

skip() { echo "netns.sh: SKIP: $*" >&2; exit 77; }

check() {
  [ "$(id -u)" -eq 0 ] || skip "network namespaces need root (running as uid $(id -u))"
  command -v ip >/dev/null || skip "iproute2 (ip) is not installed"
  command -v iptables >/dev/null || skip "iptables is not installed (apt-get install iptables)"
  local ns="jnfcheck$$"
  ip netns add "$ns" 2>/dev/null || skip "ip netns add is not permitted here"
  local ok=1
  ip -n "$ns" link add jnfc0 type veth peer name jnfc1 2>/dev/null || ok=0
  [ $ok -eq 1 ] && { ip netns exec "$ns" iptables -A OUTPUT -d 10.213.250.2 -j DROP 2>/dev/null || ok=2; }
  [ $ok -eq 1 ] && { ip netns exec "$ns" iptables -A INPUT -m statistic --mode random \
                       --probability 0.05 -j DROP 2>/dev/null || ok=3; }
  ip netns del "$ns"
  case $ok in
    0) skip "veth pairs cannot be made in a namespace" ;;
    2) skip "the kernel refuses iptables rules in a namespace" ;;
    3) skip "the kernel refuses iptables' statistic match (packet loss)" ;;
  esac
  exit 0
}

up() {
  local p=$1 n=$2
  ip netns add "$p-l" || exit 1
  ip -n "$p-l" link set lo up
  for ((k = 0; k < n; k++)); do
    ip netns add "$p-w$k" || exit 1
    ip -n "$p-w$k" link set lo up
    ip link add "$p-l$k" netns "$p-l" type veth peer name "$p-w$k" netns "$p-w$k" || exit 1
    ip -n "$p-l" addr add "$(learner_ip $k)/30" dev "$p-l$k"
    ip -n "$p-w$k" addr add "$(worker_ip $k)/30" dev "$p-w$k"
    ip -n "$p-l" link set "$p-l$k" up
    ip -n "$p-w$k" link set "$p-w$k" up
  done
}

down() {
  local p=$1 n=$2
  for ((k = 0; k < n; k++)); do ip netns del "$p-w$k" 2>/dev/null; done
  ip netns del "$p-l" 2>/dev/null
  return 0
}

partition() {
  local p=$1 k=$2 dir=$3
  case $dir in
    to_learner|both) ip netns exec "$p-w$k" iptables -A OUTPUT -d "$(learner_ip $k)" -j DROP ;;&
    to_worker|both) ip netns exec "$p-l" iptables -A OUTPUT -d "$(worker_ip $k)" -j DROP ;;
    to_learner) ;;
    *) echo "netns.sh: partition direction must be to_learner, to_worker or both" >&2; exit 2 ;;
  esac
}

heal() {
  local p=$1 k=$2
  while ip netns exec "$p-w$k" iptables -D OUTPUT -d "$(learner_ip $k)" -j DROP 2>/dev/null; do :; done
  while ip netns exec "$p-l" iptables -D OUTPUT -d "$(worker_ip $k)" -j DROP 2>/dev/null; do :; done
  return 0
}

loss() {
  local p=$1 n=$2 percent=$3
  local prob
  prob=$(awk -v x="$percent" 'BEGIN { printf "%.4f", x / 100 }')
  # INPUT holds only loss rules (partitions are OUTPUT rules): flush and set anew.
  ip netns exec "$p-l" iptables -F INPUT
  for ((k = 0; k < n; k++)); do
    ip netns exec "$p-w$k" iptables -F INPUT
    if [ "$percent" != "0" ]; then
      ip netns exec "$p-w$k" iptables -A INPUT -i "$p-w$k" -m statistic --mode random --probability "$prob" -j DROP
      ip netns exec "$p-l" iptables -A INPUT -i "$p-l$k" -m statistic --mode random --probability "$prob" -j DROP
    fi
  done
}

cmd=${1:-}
shift || true
case $cmd in
  check) check ;;
  up) up "$@" ;;
  down) down "$@" ;;
  partition) partition "$@" ;;
  heal) heal "$@" ;;
  loss) loss "$@" ;;
  *) echo "usage: netns.sh check | up P N | down P N | partition P K DIR | heal P K | loss P N PERCENT" >&2; exit 2 ;;
esac
