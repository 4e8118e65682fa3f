#!/usr/bin/env bash
# stress_suite.sh [RUNS] [BUILD_DIR]: runs the whole ctest suite RUNS times in a row (default 20)
# while two busy loops load the machine, and stops at the first failing run. The suite must pass
# every time: no test may depend on timing (docs: tests never decide an outcome by a sleep).
set -euo pipefail
runs=${1:-20}
build=${2:-build}
busy=()
cleanup() { for p in "${busy[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
for _ in 1 2; do
  (while :; do :; done) &
  busy+=($!)
done
for i in $(seq 1 "$runs"); do
  start=$(date +%s)
  if ! out=$(ctest --test-dir "$build" -j "$(nproc)" 2>&1); then
    echo "$out" | grep -E "Failed|\*\*\*|tests passed" >&2
    echo "run $i of $runs FAILED" >&2
    exit 1
  fi
  echo "run $i of $runs: $(echo "$out" | grep -E 'tests passed') ($(( $(date +%s) - start )) s)"
done
echo "$runs of $runs runs passed under load"
