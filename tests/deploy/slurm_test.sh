#!/usr/bin/env bash
# deploy/slurm runs on a real single-node Slurm (Debian's slurmctld + slurmd + munge, started
# here in the background and stopped by PID): the job trains the right-foot config with 2 workers,
# survives `scancel` of one worker step, and after `scontrol requeue` the learner resumes from
# its checkpoint (the policy version does not go back to 0).
#   tests/deploy/slurm_test.sh BUILD_DIR
set -euo pipefail
source "$(dirname "$0")/lib.sh"
need slurmctld slurmd munged sbatch squeue scancel scontrol openssl curl
BUILD_DIR=$(cd "${1:-$REPO/build/release}" && pwd)
[ "$(id -u)" = 0 ] || { echo "SKIP: starting munged and slurmd needs root"; exit 77; }

TMP=$(mktemp -d /var/tmp/juggle-slurm.XXXXXX)
chmod 755 "$TMP"
PIDS=()
JOB=""
cleanup() {
  [ -n "$JOB" ] && scancel "$JOB" 2>/dev/null && sleep 2
  for pid in "${PIDS[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${PIDS[@]}"; do
    for _ in $(seq 20); do kill -0 "$pid" 2>/dev/null || break; sleep 0.5; done
    kill -KILL "$pid" 2>/dev/null || true
  done
  if [ "${KEEP:-0}" = 1 ]; then echo "kept $TMP"; else rm -rf "$TMP"; fi
}
trap cleanup EXIT

# munge: Debian's key, a socket of our own.
mkdir -p "$TMP/munge" && chown munge:munge "$TMP/munge" && chmod 755 "$TMP/munge"  # munged: a searchable socket folder
runuser -u munge -- /usr/sbin/munged --foreground --socket="$TMP/munge/munge.socket" \
  --pid-file="$TMP/munge/munged.pid" --log-file="$TMP/munge/munged.log" \
  --seed-file="$TMP/munge/munged.seed" > "$TMP/munge/stdout" 2>&1 &
PIDS+=($!)
wait_for 10 "munged is up" test -S "$TMP/munge/munge.socket" || die "munged did not start"

CTLD_PORT=$(free_port); SLURMD_PORT=$(free_port)
mkdir -p "$TMP/state" "$TMP/spool"
export SLURM_CONF="$TMP/slurm.conf"
# CPUs=4 on a 2-core machine (config_overrides): one learner and two workers as 3 job steps.
cat > "$SLURM_CONF" <<CONF
ClusterName=juggletest
SlurmctldHost=localhost
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$TMP/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$TMP/state
SlurmdSpoolDir=$TMP/spool
SlurmctldPidFile=$TMP/slurmctld.pid
SlurmdPidFile=$TMP/slurmd.pid
SlurmctldLogFile=$TMP/slurmctld.log
SlurmdLogFile=$TMP/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SlurmdParameters=config_overrides
ReturnToService=2
JobRequeue=1
MpiDefault=none
NodeName=localhost CPUs=4 State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
slurmctld -D -i -f "$SLURM_CONF" > "$TMP/slurmctld.out" 2>&1 &
PIDS+=($!)
slurmd -D -N localhost -f "$SLURM_CONF" > "$TMP/slurmd.out" 2>&1 &
PIDS+=($!)
node_idle() { [ "$(sinfo -h -N -o %t 2>/dev/null)" = idle ]; }
wait_for 60 "the single-node cluster is idle (sinfo)" node_idle \
  || { tail -20 "$TMP/slurmctld.log" "$TMP/slurmd.log"; die "Slurm did not come up"; }

PORT=$(free_port); METRICS=$(free_port)
RUN_DIR="$TMP/run"
cd "$REPO"
JOB=$(sbatch --parsable --ntasks=3 --cpus-per-task=1 --output="$TMP/job-%j.log" \
  --export=ALL,RUN_DIR="$RUN_DIR",PORT="$PORT",METRICS_PORT="$METRICS",JUGGLE="$BUILD_DIR/juggle",JUGGLE_WORKER="$BUILD_DIR/juggle-worker" \
  deploy/slurm/juggle.sbatch configs/right_foot.textproto)
log "submitted job $JOB (learner gRPC :$PORT, metrics :$METRICS)"
show() { tail -n 25 "$TMP/job-$JOB.log" 2>/dev/null; squeue -s 2>/dev/null; }

wait_for 90 "2 workers registered" metric_at_least "$METRICS" juggle_workers_connected 2 || { show; die "workers"; }
wait_for 120 "policy version >= 3" metric_at_least "$METRICS" juggle_policy_version 3 || { show; die "no training"; }

# Cancel one worker step: the other worker keeps training.
STEP=$(squeue -h -s -j "$JOB" -o "%i %j" | awk '$2 == "worker2" { print $1 }')
[ -n "$STEP" ] || { show; die "no step named worker2"; }
log "scancel $STEP (the step of worker2)"
scancel "$STEP"
wait_for 60 "the learner sees 1 worker" metric_equals "$METRICS" juggle_workers_connected 1 || { show; die "worker step"; }
v=$(metric "$METRICS" juggle_policy_version)
wait_for 120 "training continues with 1 worker (version > $((v + 2)))" \
  metric_at_least "$METRICS" juggle_policy_version $((v + 3)) || { show; die "training stopped"; }

# A checkpoint, then requeue: the job is cancelled and runs again as the same job id.
has_checkpoint() { compgen -G "$RUN_DIR/checkpoints/*" >/dev/null; }
wait_for 180 "a checkpoint exists" has_checkpoint || { show; die "no checkpoint"; }
before=$(metric "$METRICS" juggle_policy_version)
log "scontrol requeue $JOB at policy version $before"
scontrol requeue "$JOB"
learner_gone() { ! curl -sf --max-time 1 "http://127.0.0.1:$METRICS/healthz" >/dev/null; }
wait_for 60 "the requeued job's learner stopped" learner_gone || die "requeue did not stop the job"
# Slurm holds a requeued job back (BeginTime about 2 minutes ahead) once it is pending again;
# start it now.
job_pending() { [ "$(squeue -h -j "$JOB" -o %T 2>/dev/null)" = PENDING ]; }
wait_for 60 "the job is pending again" job_pending || { show; die "the requeued job is not pending"; }
scontrol update JobId="$JOB" StartTime=now || die "cannot move the requeued job's start time"
wait_for 180 "the job runs again and its learner answers" metric_at_least "$METRICS" juggle_policy_version 1 \
  || { show; die "the requeued job did not start"; }
after=$(metric "$METRICS" juggle_policy_version)
log "resumed at policy version $after (was $before before the requeue)"
awk -v a="$after" 'BEGIN { exit !(a >= 10) }' || { show; die "the resumed learner started over ($after)"; }
grep -q "resuming from the run directory's newest checkpoint" "$TMP/job-$JOB.log" \
  || { show; die "the job log does not show the resume"; }
grep -q "restart 1" "$TMP/job-$JOB.log" || { show; die "SLURM_RESTART_COUNT is not 1"; }
wait_for 90 "both workers registered again" metric_equals "$METRICS" juggle_workers_connected 2 \
  || { show; die "workers after the requeue"; }
wait_for 120 "training goes on" metric_at_least "$METRICS" juggle_policy_version $((after + 3)) \
  || { show; die "no training after the requeue"; }

scancel "$JOB"
job_gone() { [ -z "$(squeue -h -j "$JOB" 2>/dev/null)" ]; }
wait_for 60 "scancel ends the job" job_gone || die "the job did not end"
JOB=""
log "PASS"
