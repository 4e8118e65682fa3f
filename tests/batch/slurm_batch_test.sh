#!/usr/bin/env bash
# slurm_batch_test.sh GSLIFT: `gslift batch` on a real Slurm (issue 16). Starts munged, slurmctld
# and slurmd (Debian's slurm-wlm + munge, .ci/install) on this machine as one node with 2 CPUs on
# loopback, in a temporary state folder, without systemd, and checks:
#   1. a job array of 2 tasks over 4 tiny embedded-OR captures, one of them corrupt: 3 captures
#      done with their markers, 1 recorded failed with its reason, _summary.json merged over both
#      shards, task exit codes 6 (some captures failed) and 0 (docs/batch-cluster.md);
#   2. preemption: one task cancelled mid-capture with scancel (SIGTERM) and one killed with
#      SIGKILL leave no half-written file and no marker on an unfinished capture;
#      resubmitting the array redoes only the unfinished captures, and a node already in the
#      stage cache is loaded, not rerun;
#   3. the nightly `--discover` case through sbatch, twice, with a capture added in between.
# Exits 4 (ctest: skipped) when Slurm cannot start here (not installed, not root). Every wait is a
# poll with a deadline; nothing is decided by a sleep.
set -euo pipefail
GSLIFT=$(realpath "$1")
HERE=$(cd "$(dirname "$0")" && pwd)
GRAPH=$HERE/tiny.yaml
CHECK="python3 $HERE/check_outputs.py"
skip() { echo "SKIPPED: $*"; exit 4; }
fail() { echo "FAIL: $*"; exit 1; }

for tool in munged slurmctld slurmd sbatch squeue scontrol scancel; do
  command -v "$tool" >/dev/null || skip "$tool not found (slurm-wlm and munge: bash .ci/install)"
done
[ "$(id -u)" -eq 0 ] || skip "starting munged, slurmctld and slurmd here needs root"

D=$(mktemp -d /tmp/gslift_slurm_XXXXXX)
# A stage cache of its own: never the user's, never one left by an earlier test run.
export GSLIFT_STAGE_CACHE="$D/stage-cache"
chmod 711 "$D"  # munged wants execute permission for all on its socket's folders
pids=()
cleanup() {
  set +e
  if [ -n "${SLURM_CONF:-}" ]; then
    # Jobs first (this private cluster's only), so that no task outlives its slurmd.
    scancel --full --signal=KILL --user=root >/dev/null 2>&1
    local deadline=$((SECONDS + 20))
    while [ -n "$(squeue -h 2>/dev/null)" ] && [ $SECONDS -lt $deadline ]; do sleep 0.2; done
    scontrol shutdown >/dev/null 2>&1
  fi
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
  if [ -n "${GSLIFT_KEEP_SCRATCH:-}" ]; then echo "kept $D"; else rm -rf "$D"; fi
}
trap cleanup EXIT

# Polls `condition` every 0.2 s until it succeeds or `seconds` pass.
wait_for() {
  local seconds=$1 what=$2
  shift 2
  local deadline=$((SECONDS + seconds))
  until "$@"; do
    [ $SECONDS -lt $deadline ] || fail "timed out after ${seconds}s waiting for $what"
    sleep 0.2
  done
}

# --- munge and Slurm, one node -------------------------------------------------------------------
mkdir -p "$D/munge" "$D/state" "$D/spool" "$D/work"
chmod 711 "$D/munge"
head -c 1024 /dev/urandom >"$D/munge/munge.key"
chmod 400 "$D/munge/munge.key"
munged -F --socket="$D/munge/sock" --key-file="$D/munge/munge.key" --log-file="$D/munge/log" \
  --pid-file="$D/munge/pid" --seed-file="$D/munge/seed" &
pids+=($!)
wait_for 10 munged test -S "$D/munge/sock"

read -r CTLD_PORT SLURMD_PORT < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
cat >"$D/slurm.conf" <<EOF
ClusterName=gslifttest
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
AuthType=auth/munge
AuthInfo=socket=$D/munge/sock
CredType=cred/munge
StateSaveLocation=$D/state
SlurmdSpoolDir=$D/spool
SlurmctldPidFile=$D/slurmctld.pid
SlurmdPidFile=$D/slurmd.pid
SlurmctldLogFile=$D/slurmctld.log
SlurmdLogFile=$D/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
# scancel: SIGTERM first, SIGKILL KillWait seconds later (a time limit does the same).
KillWait=10
MinJobAge=600
NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 RealMemory=1000 State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$D/slurm.conf
slurmctld -D -c -i >"$D/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N localhost >"$D/slurmd.out" 2>&1 &
pids+=($!)
node_idle() { sinfo -h -o %T 2>/dev/null | grep -q idle; }
if ! (deadline=$((SECONDS + 30)); until node_idle; do [ $SECONDS -lt $deadline ] || exit 1; sleep 0.2; done); then
  tail -5 "$D/slurmctld.log" "$D/slurmd.log" 2>/dev/null
  skip "slurmctld/slurmd did not bring the node up within 30 s"
fi
echo "slurm up: node idle (ports $CTLD_PORT/$SLURMD_PORT) after ${SECONDS}s"

# --- captures ----------------------------------------------------------------------------------
export GSLIFT_CACHE=$D/cache
W=$D/work
for s in 0 1 2; do
  "$GSLIFT" synth --out "$W/in/or_$s" --seed "$s" --views 4 --width 64 --height 48 --log-level warn
done
cp -r "$W/in/or_0" "$W/in/or_corrupt"
head -c 100 "$W/in/or_0/images/cam_01.png" >"$W/in/or_corrupt/images/cam_01.png"
printf 'in/or_0\nin/or_1\nin/or_corrupt\nin/or_2\n' >"$W/manifest.txt"

# Submits an array of tasks running `gslift batch ARGS...` (no --shard: from Slurm), prints the id.
submit() {
  local array=$1 log=$2
  shift 2
  sbatch --parsable --array="$array" --cpus-per-task=1 -o "$log-%a.log" -D "$W" \
    --wrap "exec $GSLIFT batch $* --threads 1"
}
job_gone() { [ -z "$(squeue -h -j "$1" 2>/dev/null)" ]; }
# "task exit:signal" per array task, from slurmctld's record (no accounting database here).
task_exits() {
  scontrol -o show job "$1" | sed -n 's/.*ArrayTaskId=\([0-9]*\) .*JobState=\([A-Z]*\) .* ExitCode=\([0-9:]*\) .*/\1 \2 \3/p' | sort
}

# --- 1. an array over 4 captures, one corrupt -----------------------------------------------------
job=$(submit 0-1 "$W/first" manifest.txt "$GRAPH" --out out)
wait_for 120 "job array $job" job_gone "$job"
echo "1. job array $job: $(task_exits "$job" | tr '\n' ';')"
cat "$W"/first-*.log | grep -E "shard|done,|error" || true
for c in or_0 or_1 or_2; do
  [ -f "$W/out/$c/_DONE" ] || fail "$c has no _DONE"
done
[ -f "$W/out/or_corrupt/_FAILED.json" ] || fail "or_corrupt has no _FAILED.json"
[ ! -e "$W/out/or_corrupt/_DONE" ] || fail "or_corrupt has a _DONE"
grep -q "cam_01.png: not a readable image" "$W/out/or_corrupt/_FAILED.json" ||
  fail "the failure reason does not name the corrupt image: $(cat "$W/out/or_corrupt/_FAILED.json")"
python3 - "$W/out/_summary.json" <<'EOF' || fail "the merged summary is wrong"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["shards_merged"] == [0, 1] and s["shard_count"] == 2, s
assert (s["done"], s["failed"], s["skipped"]) == (3, 1, 0), s
assert [c["name"] for c in s["captures"]] == ["or_0", "or_1", "or_2", "or_corrupt"], s
EOF
# Index 2 (or_corrupt) is shard 0's: it exits 6, shard 1 exits 0.
[ "$(task_exits "$job")" = "$(printf '0 FAILED 6:0\n1 COMPLETED 0:0')" ] ||
  fail "exit codes: $(task_exits "$job")"
$CHECK batch "$W/out" || fail "incomplete files after the first array"

# --- 2. preemption: SIGTERM and SIGKILL mid-capture, then a resubmission -------------------------
# Four good captures; or_0 is finished beforehand. Shard 0 then skips or_0 and is cancelled
# (scancel: SIGTERM) in or_2; shard 1 is killed (SIGKILL) in or_1; or_3 never starts. 3000 iterations:
# about 20 s a capture, so both cancellations land mid-capture.
"$GSLIFT" synth --out "$W/in/or_3" --seed 3 --views 4 --width 64 --height 48 --log-level warn
printf 'in/or_0\nin/or_1\nin/or_2\nin/or_3\n' >"$W/good.txt"
printf 'in/or_0\n' >"$W/first_only.txt"
"$GSLIFT" batch "$W/first_only.txt" "$GRAPH" --out "$W/pre" --threads 1 --log-level warn >/dev/null
[ -f "$W/pre/or_0/_DONE" ] || fail "or_0 did not finish outside Slurm"
done_at=$(stat -c %y "$W/pre/or_0/_DONE")
job=$(submit 0-1 "$W/pre" "good.txt $GRAPH --out pre --set iterations=3000")
# Mid-capture: the capture's own log (its gslift run child's, in the unfinished folder) shows
# its reconstruction optimising.
running() { grep -qE "recon +[0-9]+% step [0-9]+/" "$W/pre/.$1.partial/gslift.log" 2>/dev/null; }
wait_for 60 "or_2 to reach recon (shard 0)" running or_2 0
wait_for 60 "or_1 to reach recon (shard 1)" running or_1 1
scancel "${job}_0"                      # SIGCONT + SIGTERM to the task: gslift stops cleanly
# SIGKILL with no SIGTERM before it (the OOM killer, or a time limit whose KillWait ran out while
# gslift was still cleaning up): straight to the task's processes. `scancel --signal=KILL` would
# not do it: on a whole job Slurm 22.05 turns it into its ordinary termination, SIGTERM first.
task_pids() { # listpids wants the task's own job id, not ARRAY_TASK
  local id
  id=$(squeue -h -r -j "$1" -o %A 2>/dev/null)
  [ -n "$id" ] && scontrol listpids "$id" 2>/dev/null | awk 'NR > 1 && $1 ~ /^[0-9]+$/ {print $1}'
}
has_pids() { [ -n "$(task_pids "$1")" ]; }
wait_for 30 "the pids of task ${job}_1" has_pids "${job}_1"
victims=$(task_pids "${job}_1")
echo "   SIGKILL to task ${job}_1's processes: $(ps -o pid=,comm= -p $(echo $victims | tr ' ' ,) | tr '\n' ' ')"
kill -KILL $victims
gone() { ! ps -o stat= -p "$(echo $victims | tr ' ' ,)" | grep -qv '^Z'; }
wait_for 20 "the killed processes to end" gone
wait_for 60 "the cancelled array $job" job_gone "$job"
echo "2. cancelled array $job: $(task_exits "$job" | tr '\n' ';')"
grep -h "interrupted" "$W"/pre-0.log | head -2 || true
for c in or_1 or_2 or_3; do
  [ ! -e "$W/pre/$c" ] || fail "$c has a result folder although its task was cancelled"
done
[ ! -e "$W/pre/.or_2.partial" ] || fail "SIGTERM left .or_2.partial behind"
[ -d "$W/pre/.or_1.partial" ] || fail "SIGKILL should have left or_1 unfinished in .or_1.partial"
[ "$(task_exits "$job")" = "$(printf '0 CANCELLED 130:0\n1 FAILED 0:9')" ] ||
  fail "exit codes of the cancelled tasks: $(task_exits "$job")"
$CHECK batch "$W/pre" || fail "incomplete files after the cancellations"
job=$(submit 0-1 "$W/resub" "good.txt $GRAPH --out pre")
wait_for 120 "the resubmitted array $job" job_gone "$job"
echo "   resubmitted array $job: $(task_exits "$job" | tr '\n' ';')"
python3 - "$W/pre/_summary.json" <<'EOF' || fail "the resubmission did not redo exactly the unfinished captures"
import json, sys
s = json.load(open(sys.argv[1]))
status = {c["name"]: c["status"] for c in s["captures"]}
assert status == {"or_0": "skipped", "or_1": "done", "or_2": "done", "or_3": "done"}, status
EOF
[ "$(stat -c %y "$W/pre/or_0/_DONE")" = "$done_at" ] || fail "or_0's marker was rewritten"
[ ! -e "$W/pre/.or_1.partial" ] || fail "the rerun left SIGKILL's .or_1.partial behind"
$CHECK batch "$W/pre" || fail "incomplete files after the resubmission"
# The stage cache across submissions: the same captures into a new folder load every node that
# has a binary form (the capture itself is always read) instead of reconstructing again.
job=$(submit 0-1 "$W/again" "good.txt $GRAPH --out again")
wait_for 120 "the array over finished captures" job_gone "$job"
python3 - "$W/again" <<'EOF' || fail "a node already in the stage cache ran again"
import json, sys
for c in ["or_0", "or_1", "or_2", "or_3"]:
    run = json.load(open(f"{sys.argv[1]}/{c}/run.json"))
    cache = {n["id"]: n["cache"] for n in run["nodes"]}
    assert cache["capture"] == "off", (c, cache)
    assert all(v == "hit" for k, v in cache.items() if k != "capture"), (c, cache)
EOF
echo "   the same captures again: every cacheable node loaded from the stage cache"

# --- 3. nightly: --discover through sbatch, twice -------------------------------------------------
mkdir -p "$W/night"
cp -r "$W/in/or_0" "$W/night/or_mon"
job=$(submit 0-1 "$W/mon" --discover night "$GRAPH" --out nightly)
wait_for 60 "the first nightly array" job_gone "$job"
[ -f "$W/nightly/or_mon/_DONE" ] || fail "or_mon was not processed"
mon_at=$(stat -c %Y "$W/nightly/or_mon/_DONE")
cp -r "$W/in/or_1" "$W/night/.or_tue" && mv "$W/night/.or_tue" "$W/night/or_tue"
job=$(submit 0-1 "$W/tue" --discover night "$GRAPH" --out nightly)
wait_for 60 "the second nightly array" job_gone "$job"
[ -f "$W/nightly/or_tue/_DONE" ] || fail "or_tue was not processed"
[ "$(stat -c %Y "$W/nightly/or_mon/_DONE")" = "$mon_at" ] || fail "or_mon was processed again"
# Each array task discovers on its own: one finds or_tue; the other finds it too, or, when it starts
# after the first has finished the tiny capture, nothing. Neither may find or_mon again.
if grep -h "discovered" "$W"/tue-*.log | grep -Eqv "discovered [01] capture" ||
  ! grep -qh "discovered 1 capture" "$W"/tue-*.log; then
  fail "the second night discovered more than or_tue: $(grep -h discovered "$W"/tue-*.log)"
fi
$CHECK batch "$W/nightly" || fail "incomplete files after the nightly runs"
echo "PASS in ${SECONDS}s"
