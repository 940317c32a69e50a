# Helpers of the deployment tests (sourced): skipping, waiting, metrics, certificates.
# Every test starts its daemons itself and stops them by PID (no systemd here).
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
export CONTAINERS_CONF=${CONTAINERS_CONF:-$REPO/deploy/podman/containers.conf}

log() { echo "[$(date +%T)] $*"; }
die() { echo "FAIL: $*" >&2; exit 1; }
# Exit 77 (ctest SKIP_RETURN_CODE) when a tool is missing; make test-deploy installs them.
need() {
  for tool in "$@"; do
    command -v "$tool" >/dev/null || { echo "SKIP: $tool missing (scripts/dev/install_deps.sh --deploy)"; exit 77; }
  done
}

# wait_for SECONDS DESCRIPTION COMMAND...: polls every second until COMMAND succeeds.
wait_for() {
  local limit=$1 what=$2; shift 2
  local start=$SECONDS
  until "$@" >/dev/null 2>&1; do
    (( SECONDS - start >= limit )) && { log "timed out after ${limit}s: $what"; return 1; }
    sleep 1
  done
  log "$what (after $((SECONDS - start)) s)"
}

# metric PORT NAME: the value of an unlabelled metric on the learner's 127.0.0.1:PORT/metrics
# (empty if the learner does not answer).
metric() {
  curl -sf --max-time 2 "http://127.0.0.1:$1/metrics" | awk -v n="$2" '$1 == n { print $2 }'
}
# metric_at_least PORT NAME VALUE
metric_at_least() {
  local v; v=$(metric "$1" "$2"); [ -n "$v" ] && awk -v a="$v" -v b="$3" 'BEGIN { exit !(a >= b) }'
}

# free_port: a TCP port nothing listens on now, drawn below the kernel's ephemeral range
# (ip_local_port_range): a port the kernel hands out itself (bind to 0) can be handed again to
# any client socket (srun's, slurmd's) before the learner binds it — stop 55's CI failure.
free_port() {
  /usr/bin/python3 - <<'PY'
import random, socket
low = int(open("/proc/sys/net/ipv4/ip_local_port_range").read().split()[0])
for _ in range(200):
    port = random.randrange(10000, max(low, 10001))
    s = socket.socket()
    try:
        s.bind(("127.0.0.1", port)); print(port); break
    except OSError:
        pass
    finally:
        s.close()
else:
    raise SystemExit("free_port: no free port below %d" % low)
PY
}

# make_secrets DIR NAME...: a token, a CA and a learner certificate for the DNS names / IPs
# given (first one is the CN), as deploy/slurm/juggle.sbatch makes them.
make_secrets() {
  local dir=$1; shift
  mkdir -p "$dir" && chmod 700 "$dir"
  local san="" n
  for n in "$@"; do
    if [[ $n =~ ^[0-9.]+$ ]]; then san+="IP:$n,"; else san+="DNS:$n,"; fi
  done
  (
    cd "$dir"
    openssl rand -hex 32 > token
    openssl ecparam -name prime256v1 -genkey -noout -out ca.key
    openssl req -x509 -new -key ca.key -out ca.pem -days 2 -subj /CN=juggle-test-ca
    openssl ecparam -name prime256v1 -genkey -noout -out learner.key
    openssl req -new -key learner.key -out learner.csr -subj "/CN=$1"
    printf 'subjectAltName=%s\n' "${san%,}" > learner.ext
    openssl x509 -req -in learner.csr -CA ca.pem -CAkey ca.key -CAcreateserial \
      -out learner.pem -days 2 -extfile learner.ext
  ) >/dev/null 2>&1 || die "openssl could not make the test secrets"
}
# metric_equals PORT NAME VALUE
metric_equals() {
  local v; v=$(metric "$1" "$2"); [ -n "$v" ] && awk -v a="$v" -v b="$3" 'BEGIN { exit !(a == b) }'
}
