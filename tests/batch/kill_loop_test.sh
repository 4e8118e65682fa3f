#!/usr/bin/env bash
# kill_loop_test.sh GSLIFT [KILLS]: kill -9 of `gslift run` and of `gslift batch` at random moments
# (issue 16), until KILLS of each (default 20) landed while the command ran; the moments are drawn
# from a fixed seed over the duration of one uninterrupted run, measured first. After every kill
# the output folder must hold only complete files (check_outputs.py: JSON parses, PNG and PLY
# whole, every batch capture folder marked once, unfinished work only in temporaries nothing
# reads), and every 10th try, after the last kill and whenever a batch has finished, a rerun of
# the same command must finish the work. The sleep before each kill only picks the moment; the
# outcome is decided by the checks.
set -euo pipefail
shopt -s nullglob
GSLIFT=$(realpath "$1")
KILLS=${2:-20}
HERE=$(cd "$(dirname "$0")" && pwd)
GRAPH=$HERE/tiny.yaml
check() { python3 "$HERE/check_outputs.py" "$@" >"$D/check.txt" || { cat "$D/check.txt"; fail "incomplete files ($*)"; }; }
fail() { echo "FAIL: $*"; exit 1; }

D=$(mktemp -d /tmp/gslift_kill_XXXXXX)
# A stage cache of its own: never the user's, never one left by an earlier test run.
export GSLIFT_STAGE_CACHE="$D/stage-cache"
trap '[ -n "${GSLIFT_KEEP_SCRATCH:-}" ] && echo "kept $D" || rm -rf "$D"' EXIT
export GSLIFT_CACHE=$D/cache
RANDOM=16  # the kill moments repeat from run to run

# Starts a command in the background and kills it with SIGKILL after a random 0..max_ms scaled by
# reach_pct. A kill that comes after the command ended shrinks reach_pct by a quarter (to 10% at
# least): the measured duration is an upper bound that other load on the machine can make far too
# long (the warm-cache runs are shorter too), and kills drawn past the end would run out of tries.
reach_pct=100
kill_at_random() {
  local max_ms=$1
  shift
  "$@" >/dev/null 2>&1 &
  local pid=$! ms=$((RANDOM % (max_ms * reach_pct / 100 + 1)))
  sleep "$(printf '%d.%03d' $((ms / 1000)) $((ms % 1000)))"
  if kill -KILL "$pid" 2>/dev/null; then
    killed=$((killed + 1))
  else
    reach_pct=$((reach_pct * 3 / 4 > 10 ? reach_pct * 3 / 4 : 10))
  fi
  wait "$pid" 2>/dev/null || true
}

# 60 iterations: about 0.3 s a capture (0.45 s for gslift run) on the 2-core test machine.
SET=(--set iterations=60 --threads 1)

# A rerun without a kill finishes the work, leaves no temporary, and the next try starts afresh.
rerun_run() {
  "$GSLIFT" run "$GRAPH" --out "$D/run" "${SET[@]}" >/dev/null 2>&1 || fail "rerun $tries of gslift run failed"
  check run "$D/run"
  grep -q " 0 unfinished temporaries" "$D/check.txt" || fail "the rerun left temporaries: $(cat "$D/check.txt")"
  python3 -c 'import json,sys; assert json.load(open(sys.argv[1]))["run"]["status"] == "ok"' \
    "$D/run/run.json" || fail "rerun $tries: run.json is not ok"
  reruns=$((reruns + 1))
  rm -rf "$D/run"
}
rerun_batch() {
  "$GSLIFT" batch "$D/manifest.txt" "$GRAPH" --out "$D/batch" "${SET[@]}" >"$D/rerun.txt" 2>&1 ||
    fail "rerun $tries of gslift batch failed: $(tail -5 "$D/rerun.txt")"
  check batch "$D/batch"
  all_done || fail "rerun $tries: not every capture is done"
  if ls -A "$D/batch" | grep -q '\.partial$'; then fail "rerun $tries left a .partial folder"; fi
  reruns=$((reruns + 1))
  rm -rf "$D/batch"
}

# The kill moments are drawn over one uninterrupted run's duration, measured here, so that most
# kills land on any machine.
duration_ms() {
  local t0
  t0=$(date +%s%N)
  "$@" >/dev/null 2>&1 || { echo "FAIL: an uninterrupted gslift $2 failed" >&2; exit 1; }
  echo $((($(date +%s%N) - t0) / 1000000 + 1))
}

# Kills until KILLS of them landed while the command was running (at most 3 x KILLS tries).
# --- gslift run: a fresh embedded capture cache every other time, so kills land in its
# generation too.
run_ms=$(duration_ms "$GSLIFT" run "$GRAPH" --out "$D/run" "${SET[@]}")
rm -rf "$D/run"
killed=0
tries=0
reruns=0
while [ $killed -lt "$KILLS" ]; do
  tries=$((tries + 1))
  [ $tries -le $((3 * KILLS)) ] || fail "only $killed of $tries kills landed while gslift run ran"
  [ $((tries % 2)) -eq 1 ] && rm -rf "$GSLIFT_CACHE"
  kill_at_random "$run_ms" "$GSLIFT" run "$GRAPH" --out "$D/run" "${SET[@]}"
  check run "$D/run"
  if [ $((tries % 10)) -eq 0 ] || [ $killed -eq "$KILLS" ]; then rerun_run; fi
done
echo "gslift run (${run_ms} ms uninterrupted): $killed kills in $tries tries at random moments, outputs complete after each; $reruns reruns finished the work"

# --- gslift batch over 3 captures; once all are done, a rerun checks them and the next try
# starts over.
for s in 0 1 2; do
  "$GSLIFT" synth --out "$D/in/or_$s" --seed "$s" --views 4 --width 64 --height 48 --log-level warn >/dev/null
done
printf 'in/or_0\nin/or_1\nin/or_2\n' >"$D/manifest.txt"
batch_ms=$(duration_ms "$GSLIFT" batch "$D/manifest.txt" "$GRAPH" --out "$D/batch" "${SET[@]}")
rm -rf "$D/batch"
all_done() { [ -f "$D/batch/or_0/_DONE" ] && [ -f "$D/batch/or_1/_DONE" ] && [ -f "$D/batch/or_2/_DONE" ]; }
killed=0
tries=0
reruns=0
reach_pct=100
while [ $killed -lt "$KILLS" ]; do
  tries=$((tries + 1))
  [ $tries -le $((3 * KILLS)) ] || fail "only $killed of $tries kills landed while gslift batch ran"
  # A batch resumed after a kill skips the captures already done, so the moment is drawn over the
  # work left (the uninterrupted duration scaled by the captures not yet done): drawn over the
  # whole duration, most kills would come after the resumed batch ended, all the more on a slow
  # build (AddressSanitizer) where the captures, not the start-up, are most of the time.
  markers=("$D"/batch/or_*/_DONE)
  kill_at_random $((batch_ms * (3 - ${#markers[@]}) / 3 + 1)) "$GSLIFT" batch "$D/manifest.txt" "$GRAPH" --out "$D/batch" "${SET[@]}"
  check batch "$D/batch"
  if [ $((tries % 10)) -eq 0 ] || [ $killed -eq "$KILLS" ] || all_done; then rerun_batch; fi
done
echo "gslift batch (${batch_ms} ms uninterrupted): $killed kills in $tries tries at random moments, outputs complete after each; $reruns reruns finished the work"
echo "PASS in ${SECONDS}s"
