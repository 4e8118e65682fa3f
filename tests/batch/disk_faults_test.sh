#!/usr/bin/env bash
# disk_faults_test.sh GSLIFT: a full disk and an unwritable output folder (issue 16). The disk is a
# small tmpfs when this process may mount one (root), else a file-size limit (ulimit -f, SIGXFSZ
# ignored, so writes fail with EFBIG as they would with ENOSPC). Checks: exit code 73 ("cannot
# write the results"), an error naming the path and the system's reason, only complete files left
# (check_outputs.py) and no temporaries; a batch stops at the first capture it cannot write,
# leaves no .partial folder and no marker for it, and a rerun with space finishes the work.
set -euo pipefail
GSLIFT=$(realpath "$1")
HERE=$(cd "$(dirname "$0")" && pwd)
GRAPH=$HERE/tiny.yaml
fail() { echo "FAIL: $*"; exit 1; }
D=$(mktemp -d /tmp/gslift_disk_XXXXXX)
# A stage cache of its own: never the user's, never one left by an earlier test run.
export GSLIFT_STAGE_CACHE="$D/stage-cache"
mounts=()
cleanup() {
  for m in "${mounts[@]}"; do umount "$m" 2>/dev/null || true; done
  if [ -n "${GSLIFT_KEEP_SCRATCH:-}" ]; then echo "kept $D"; else rm -rf "$D"; fi
}
trap cleanup EXIT
export GSLIFT_CACHE=$D/cache
"$GSLIFT" synth --out "$D/in/or_0" --seed 0 --views 4 --width 64 --height 48 --log-level warn >/dev/null
cp -r "$D/in/or_0" "$D/in/or_1"
cp -r "$D/in/or_0" "$D/in/or_2"
printf '%s\n' "$D/in/or_0" "$D/in/or_1" "$D/in/or_2" >"$D/manifest.txt"
# Warm the embedded capture cache, so that the disk limits below hit gslift's results only.
"$GSLIFT" run "$GRAPH" --out "$D/warm" --threads 1 >/dev/null 2>&1 || fail "the tiny graph does not run"

# expect CODE PATTERN FILE: the exit code and a line of the output.
expect() {
  [ "$1" = "$rc" ] || { cat "$3"; fail "exit code $rc, expected $1"; }
  grep -Eq "$2" "$3" || { cat "$3"; fail "no '$2' in the output"; }
}
complete() {
  python3 "$HERE/check_outputs.py" "$@" >"$D/check.txt" || { cat "$D/check.txt"; fail "incomplete files"; }
  grep -q " 0 unfinished temporaries" "$D/check.txt" || { cat "$D/check.txt"; fail "temporaries left"; }
}

# GSLIFT_DISK_FAULTS=ulimit forces the file-size limit (to test the fallback as root).
if [ "${GSLIFT_DISK_FAULTS:-}" != ulimit ] && [ "$(id -u)" -eq 0 ] && mkdir -p "$D/probe" && mount -t tmpfs -o size=64k tmpfs "$D/probe" 2>/dev/null; then
  umount "$D/probe"
  mode=tmpfs
  full="No space left on device"
  # limited KB COMMAND...: runs COMMAND on a fresh tmpfs of KB kilobytes at $D/disk.
  limited() {
    local kb=$1
    shift
    umount "$D/disk" 2>/dev/null || true
    mkdir -p "$D/disk"
    mount -t tmpfs -o "size=${kb}k" tmpfs "$D/disk"
    mounts=("$D/disk")
    rc=0
    "$@" >"$D/out.txt" 2>&1 || rc=$?
  }
else
  mode="ulimit -f"
  full="File too large"
  limited() {
    local kb=$1
    shift
    rm -rf "$D/disk" && mkdir -p "$D/disk"
    rc=0
    (trap '' XFSZ; ulimit -f $((kb / 8)); exec "$@") >"$D/out.txt" 2>&1 || rc=$?
  }
fi
echo "full disk: $mode"

# --- gslift run on a disk that fills at different points -----------------------------------------
for kb in 8 16 24 32 40 48; do
  limited "$kb" "$GSLIFT" run "$GRAPH" --out "$D/disk/run" --threads 1
  expect 73 "error: .*cannot write $D/disk/run/[^ ]+: $full" "$D/out.txt"
  complete run "$D/disk/run"
done
echo "gslift run: exit 73 naming the file, only complete files, at 6 disk sizes"

# --- gslift batch: stops at the first capture it cannot write; a rerun with space finishes -------
limited 64 "$GSLIFT" batch "$D/manifest.txt" "$GRAPH" --out "$D/disk/batch" --threads 1
expect 73 "cannot write $D/disk/batch/[^ ]+: $full" "$D/out.txt"
expect 73 "stopped: results cannot be written" "$D/out.txt"
complete batch "$D/disk/batch"
if ls -A "$D/disk/batch" | grep -q partial; then fail "a .partial folder was left behind"; fi
if [ "$mode" = tmpfs ]; then
  mount -o remount,size=4m "$D/disk"
  rc=0
  "$GSLIFT" batch "$D/manifest.txt" "$GRAPH" --out "$D/disk/batch" --threads 1 >"$D/out.txt" 2>&1 || rc=$?
else
  limited 100000 "$GSLIFT" batch "$D/manifest.txt" "$GRAPH" --out "$D/disk/batch" --threads 1
fi
expect 0 "done, " "$D/out.txt"
for c in or_0 or_1 or_2; do [ -f "$D/disk/batch/$c/_DONE" ] || fail "$c not done after the rerun"; done
complete batch "$D/disk/batch"
echo "gslift batch: exit 73 and stopped cleanly on a full disk; the rerun with space finished"

# --- an unwritable output folder ------------------------------------------------------------------
mkdir -p "$D/ro"
if [ "$mode" != tmpfs ] && [ "$(id -u)" -eq 0 ]; then
  echo "unwritable --out: not tried (root without mount ignores folder permissions)"
  echo "PASS in ${SECONDS}s"
  exit 0
fi
if [ "$mode" = tmpfs ]; then
  mount -t tmpfs -o ro,size=64k tmpfs "$D/ro"
  mounts+=("$D/ro")
  why="Read-only file system"
else
  chmod 555 "$D/ro"
  why="Permission denied"
fi
rc=0
"$GSLIFT" run "$GRAPH" --out "$D/ro/run" --threads 1 >"$D/out.txt" 2>&1 || rc=$?
expect 73 "error: cannot create --out $D/ro/run: $why" "$D/out.txt"
rc=0
"$GSLIFT" run "$GRAPH" --out "$D/ro" --threads 1 >"$D/out.txt" 2>&1 || rc=$?
expect 73 "error: cannot write in --out $D/ro: $why" "$D/out.txt"
rc=0
"$GSLIFT" batch "$D/manifest.txt" "$GRAPH" --out "$D/ro/batch" >"$D/out.txt" 2>&1 || rc=$?
expect 73 "error: cannot create --out $D/ro/batch: $why" "$D/out.txt"
[ -z "$(ls -A "$D/ro")" ] || fail "something was written into the unwritable folder"
echo "unwritable --out: exit 73 naming the folder ($why), nothing written"
echo "PASS in ${SECONDS}s"
