#!/usr/bin/env bash
# Renders through a real Slurm: starts a one-node cluster on this machine from Debian's packages
# (slurm-wlm, munge; installed when missing), then
#   1. `rayforge slurm` with a job array of 4 slices and the merge job, through sbatch: the
#      merged image must be the bytes of a one-process `rayforge render`;
#   2. the scripts of `rayforge slurm --dry-run` submitted by hand (sbatch --parsable, then
#      --dependency=afterok), one task cancelled mid-slice (scancel: SIGTERM, then SIGKILL):
#      its part must be absent, the merge cancelled (afterok cannot be met), and `rayforge
#      slurm` submitted again must render only that slice and merge to the same bytes;
#   3. a running task requeued by the scheduler (`scontrol requeue`, as after a node failure):
#      it must run again from the start and the merge still give the same bytes;
# and stops the daemons it started, by the process ids it recorded, on any exit.
#
# Usage: tools/slurm/test-cluster.sh [RAYFORGE]   (default: target/debug/rayforge)
# Needs root (slurmd runs jobs as their user; munged is started as the munge user). There is no
# systemd here: the daemons run in the foreground (-D, -F) as this script's children. Their
# configuration, state, spool, logs and munge key are in a temporary directory, kept when
# RAYFORGE_SLURM_KEEP=1. Ports are picked at random so two runs on one machine do not meet.
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
rayforge=${1:-${RAYFORGE:-$repo/target/debug/rayforge}}
rayforge=$(readlink -f "$rayforge")
[ -x "$rayforge" ] || { echo "error: no rayforge executable at $rayforge" >&2; exit 2; }
[ "$(id -u)" = 0 ] || { echo "error: this test needs root (slurmd, munged as munge)" >&2; exit 2; }

started=$(date +%s%N)
say() {
  local tenths=$((($(date +%s%N) - started) / 100000000))
  printf '[%3d.%d s] %s\n' $((tenths / 10)) $((tenths % 10)) "$*"
}
fail() { say "FAILED: $*"; exit 1; }

if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  say "installing slurm-wlm and munge"
  (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge) \
    >/dev/null || fail "apt-get install slurm-wlm munge"
fi

tmp=$(mktemp -d /tmp/rayforge-slurm.XXXXXX)
# munged, running as munge, must reach its directory below this one.
chmod 755 "$tmp"
pids=()
jobs_submitted=()

# Stops what this script started, by the ids it recorded: the jobs first (so that slurmd
# leaves no step behind), then each daemon, TERM and then KILL if it has not gone in 5 s.
cleanup() {
  local status=$?
  set +e
  if [ ${#jobs_submitted[@]} -gt 0 ]; then
    scancel "${jobs_submitted[@]}" 2>/dev/null
  fi
  local i pid
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    pid=${pids[i]}
    kill -TERM "$pid" 2>/dev/null || continue
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
  done
  if [ "$status" != 0 ]; then
    for log in "$tmp"/log/*.log; do
      [ -f "$log" ] && { echo "--- last lines of $log"; tail -n 15 "$log"; }
    done
  fi
  if [ "${RAYFORGE_SLURM_KEEP:-0}" = 1 ]; then
    echo "kept $tmp"
  else
    rm -rf "$tmp"
  fi
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

host=$(hostname -s)
ctld_port=$((20000 + RANDOM % 20000))
slurmd_port=$((ctld_port + 1))
mkdir -p "$tmp"/{etc,state,spool,log,work,munge}

# munge: a key of our own, a socket of our own, the daemon as the munge user (it refuses to
# run as root), in a directory only it may write (and all may enter, to reach the socket).
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chown -R munge:munge "$tmp/munge"
chmod 755 "$tmp/munge"
chmod 400 "$tmp/munge/munge.key"
socket=$tmp/munge/munge.socket.2
setpriv --reuid=munge --regid=munge --init-groups \
  munged -F --key-file="$tmp/munge/munge.key" --socket="$socket" \
  --pid-file="$tmp/munge/munged.pid" --seed-file="$tmp/munge/munged.seed" \
  --log-file="$tmp/munge/munged.log" >"$tmp/log/munged.log" 2>&1 &
pids+=($!)

export SLURM_CONF=$tmp/etc/slurm.conf
cat >"$SLURM_CONF" <<EOF
ClusterName=rayforge-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MailProg=/bin/true
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
KillWait=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 RealMemory=500 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF

for _ in $(seq 50); do [ -S "$socket" ] && break; sleep 0.1; done
[ -S "$socket" ] || fail "munged did not start"
slurmctld -D -f "$SLURM_CONF" >"$tmp/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$host" >"$tmp/log/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
  state=$(sinfo -h -n "$host" -o %T 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.2
done
[ "$state" = idle ] || fail "the node did not come up (its state: '${state:-none}')"
say "one-node cluster up: node $host, slurmctld on port $ctld_port, $(sinfo -V)"

scene=$repo/scenes/trtc/cover.yml
work=$tmp/work
# The slices must last long enough for run 2 to cancel one mid-slice, in a debug build as in
# an optimized one: a 200×200 image with k×k rays per pixel, k chosen from the time of two
# small renders (their difference, free of the start and the scene load) so that a slice (a
# quarter of the image) takes about 2 s on one core. The work grows with the rays, not the
# pixels, so the parts stay small (1.3 MB in all).
render_ms() { # SPP : milliseconds of a 100×100 render on one core
  local t0
  t0=$(date +%s%N)
  "$rayforge" render "$scene" -o "$work/calibrate.png" --width 100 --height 100 --spp "$1" \
    --threads 1 -q
  echo $((($(date +%s%N) - t0) / 1000000))
}
ms=$((($(render_ms 16) - $(render_ms 1)) / 15)) # ≈ a 200×200 quarter at 1 ray per pixel
[ "$ms" -ge 1 ] || ms=1
k=1
while [ $((k * k * ms)) -lt 2000 ] && [ "$k" -lt 40 ]; do k=$((k + 1)); done
flags=(--width 200 --height 200 --spp $((k * k)))

# The state and exit code of a job, once it has left the queue ("" while it is in it).
finished() { squeue -h -j "$1" 2>/dev/null | grep -q . && return 1; return 0; }
state_of() { scontrol show job -o "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -n 1; }
wait_for() { # JOB... : waits until every job has left the queue (60 s at most)
  for _ in $(seq 600); do
    local all=1 job
    for job in "$@"; do finished "$job" || all=0; done
    [ "$all" = 1 ] && return 0
    sleep 0.1
  done
  squeue
  fail "jobs $* still in the queue after 60 s"
}
job_id_of() { scontrol show job -o "$1" 2>/dev/null | grep -o 'JobId=[0-9]*' | head -n 1 | cut -d= -f2; }
restarts_of() { scontrol show job -o "$1" 2>/dev/null | grep -o 'Restarts=[0-9]*' | head -n 1; }
await() { # WHAT SECONDS COMMAND... : runs COMMAND every 0.1 s until it succeeds, else fails
  local what=$1 tenths=$(($2 * 10))
  shift 2
  for _ in $(seq "$tenths"); do "$@" && return 0; sleep 0.1; done
  squeue
  fail "not within $((tenths / 10)) s: $what"
}
requeued_and_gone() { # TASK : pending again, and none of the frozen $task_pids left
  [ "$(state_of "$1")" = JobState=PENDING ] || return 1
  local pid
  for pid in $task_pids; do kill -0 "$pid" 2>/dev/null && return 1; done
  return 0
}
submit() { # OUTPUT : rayforge slurm, prints its output, sets $array and $merge
  local out
  out=$("$rayforge" slurm "$scene" -o "$1" --tasks 4 "${flags[@]}")
  printf '%s\n' "$out" | sed 's/^/    /'
  array=$(echo "$out" | awk '/^slices:/ {print $4}' | tr -d ,)
  merge=$(echo "$out" | awk '/^merge:/ {print $3}' | tr -d ,)
  [[ $array =~ ^[0-9]+$ && $merge =~ ^[0-9]+$ ]] || fail "no job ids in rayforge slurm's output"
  jobs_submitted+=("$array" "$merge")
}

freeze_a_running_task() { # sets $victim (the task index), $task_pids; uses $array
  # Freezes the processes of a running task of $array as soon as Slurm lists them, so that
  # what is done to it lands mid-slice whatever the machine's speed (Slurm sends SIGCONT
  # before SIGTERM, then SIGKILL after KillWait).
  victim=
  for _ in $(seq 300); do
    victim=$(squeue -h -r -j "$array" -t R -o %K 2>/dev/null | head -n 1)
    [ -n "$victim" ] && break
    sleep 0.05
  done
  [ -n "$victim" ] || fail "no task of $array started running"
  local job
  job=$(squeue -h -j "${array}_${victim}" -o %A)
  task_pids=
  for _ in $(seq 100); do
    task_pids=$(scontrol listpids "$job" 2>/dev/null | awk '$1 ~ /^[0-9]+$/ { print $1 }')
    [ -n "$task_pids" ] && break
    sleep 0.03
  done
  [ -n "$task_pids" ] || fail "scontrol listpids $job found no process"
  # shellcheck disable=SC2086 # one pid a word
  kill -STOP $task_pids 2>/dev/null || true
  sleep 0.5
}

say "one-process reference render, ${flags[*]} (a ray per pixel of a slice: $ms ms)"
"$rayforge" render "$scene" -o "$work/reference.png" "${flags[@]}" -q

say "run 1: 4 slices and the merge through sbatch"
submit "$work/one.png"
wait_for "$array" "$merge"
[ "$(state_of "$merge")" = JobState=COMPLETED ] || fail "the merge job ended $(state_of "$merge")"
cmp "$work/reference.png" "$work/one.png" || fail "the merged image differs from the reference"
say "run 1: merged image is byte-identical to the one-process render"

say "run 2: the scripts of --dry-run submitted by hand with sbatch, one task cancelled mid-slice"
"$rayforge" slurm "$scene" -o "$work/two.png" --tasks 4 --dry-run "${flags[@]}" | sed 's/^/    /'
array=$(cd "$work/two.png.slurm" && sbatch --parsable slices.sh)
array=${array%%;*}
merge=$(cd "$work/two.png.slurm" && sbatch --parsable --dependency=afterok:"$array" merge.sh)
merge=${merge%%;*}
jobs_submitted+=("$array" "$merge")
freeze_a_running_task
scancel "${array}_${victim}"
say "cancelled task ${array}_${victim} while it was running (pids ${task_pids//$'\n'/ })"
wait_for "$array" "$merge"
part=$work/two.png.slurm/parts/part-$victim.part
[ ! -e "$part" ] || fail "task $victim finished before it was cancelled (make its slice slower)"
[ "$(state_of "${array}_${victim}")" = JobState=CANCELLED ] \
  || fail "task $victim ended $(state_of "${array}_${victim}")"
[ "$(state_of "$merge")" = JobState=CANCELLED ] \
  || fail "the merge job ended $(state_of "$merge"), not cancelled for want of a slice"
[ ! -e "$work/two.png" ] || fail "an image was written without slice $victim"
say "task $victim left no part; the merge was cancelled; submitting with rayforge slurm again"
submit "$work/two.png"
wait_for "$array" "$merge"
[ "$(state_of "$merge")" = JobState=COMPLETED ] || fail "the merge job ended $(state_of "$merge")"
skipped=$(cat "$work"/two.png.slurm/logs/slice-*.log | grep -c 'already complete' || true)
[ "$skipped" = 3 ] || fail "$skipped slices were skipped on re-submission, not 3"
cmp "$work/reference.png" "$work/two.png" || fail "the merged image differs from the reference"
say "run 2: 3 complete slices skipped, slice $victim rendered again, merged image byte-identical"

say "run 3: a running task requeued by the scheduler (scontrol requeue), as after a node failure"
submit "$work/three.png"
freeze_a_running_task
task=${array}_${victim}
scontrol requeue "$task" || fail "scontrol requeue $task refused"
requeued_at=$(date +%s)
# A requeued job waits, pending, for a begin time Slurm sets two minutes ahead: slurmd refuses
# to launch a job whose credential is not younger than its revocation, both counted in whole
# seconds ("Job N already killed, do not launch batch job", and the task then fails, which
# cancels the merge). Moving the begin time to now is safe only once the killed instance is
# gone and the clock is past that second, so wait for exactly that, whatever the load:
# JobState=PENDING (not COMPLETING or REQUEUED), the frozen processes gone, two seconds on.
await "task $task pending, its killed instance gone" 60 requeued_and_gone "$task"
while [ "$(date +%s)" -lt $((requeued_at + 2)) ]; do sleep 0.1; done
scontrol update JobId="$task" StartTime=now \
  || fail "cannot move the requeued task's begin time to now"
say "requeued task $task while it was running; it is pending again, its begin time now"
wait_for "$array" "$merge"
if [ "$(state_of "$merge")" != JobState=CANCELLED ]; then
  [ "$(restarts_of "$task")" = Restarts=1 ] \
    || fail "task $victim was not restarted once: $(restarts_of "$task")"
elif grep -q "Job $(job_id_of "$task") already killed, do not launch batch job" "$tmp/log/slurmd.log"; then
  # slurmd refused the relaunch all the same (its revocation is kept by the second, stamped
  # by slurmctld). That is Slurm's own race, not a lost part: a user's answer is to submit the
  # same command again, and it must render only the requeued slice and merge to the same bytes.
  say "note: slurmd refused to relaunch $task (its credential revoked in the same second); submitting again"
  submit "$work/three.png"
  wait_for "$array" "$merge"
  skipped=$(cat "$work"/three.png.slurm/logs/slice-*.log | grep -c 'already complete' || true)
  [ "$skipped" = 3 ] || fail "$skipped slices were skipped on re-submission, not 3"
else
  fail "the merge job was cancelled after task $task was requeued ($(state_of "$task"))"
fi
[ "$(state_of "$merge")" = JobState=COMPLETED ] || fail "the merge job ended $(state_of "$merge")"
restarts=$(grep -c '^' "$work/three.png.slurm/logs/slice-$victim.log" || true)
cmp "$work/reference.png" "$work/three.png" || fail "the merged image differs from the reference"
say "run 3: task $victim ran again after its requeue ($restarts lines in its log), merged image byte-identical"
say "PASSED"
