#!/usr/bin/env bash
# rig_discover_test.sh GSLIFT: a recording of a multi-camera RGB-D OR rig is a folder of time
# steps (docs/or-rig.md). `gslift synth --layout rig` writes one of two time steps; `gslift batch
# --discover` runs each time step as a capture, and the summary (console and _summary.json) has
# one row per time step with its headline metrics.
set -euo pipefail
GSLIFT=$(realpath "$1")
HERE=$(cd "$(dirname "$0")" && pwd)
fail() { echo "FAIL: $*"; exit 1; }
D=$(mktemp -d /tmp/gslift_rig_discover_XXXXXX)
export GSLIFT_STAGE_CACHE="$D/stage-cache"
trap '[ -n "${GSLIFT_KEEP_SCRATCH:-}" ] && echo "kept $D" || rm -rf "$D"' EXIT
"$GSLIFT" synth --out "$D/rec" --layout rig --time-steps 2 --views 4 --width 64 --height 48 >/dev/null
[ -f "$D/rec/camera04.json" ] || fail "no calibration camera04.json"
# The preflight takes a time step as a capture holding all that LangOR needs.
"$GSLIFT" validate "$HERE/../../graphs/langor.yaml" --input "$D/rec/000000" >"$D/validate.txt" 2>&1 ||
  { cat "$D/validate.txt"; fail "validate on a rig time step"; }
"$GSLIFT" batch --discover "$D/rec" "$HERE/rig_masks.yaml" --out "$D/out" --threads 1 >"$D/batch.txt" 2>&1 ||
  { cat "$D/batch.txt"; fail "gslift batch --discover failed"; }
python3 - "$D/out/_summary.json" <<'PY' || { cat "$D/batch.txt"; fail "summary"; }
import json, sys
s = json.load(open(sys.argv[1]))
rows = s["captures"]
assert [r["name"] for r in rows] == ["000000", "000001"], rows
for r in rows:
    assert r["status"] == "done", r
    miou = r["metrics"]["eval.mIoU"]
    assert 0 < miou <= 100, r
# The time steps hold the same frames: the same score.
assert rows[0]["metrics"] == rows[1]["metrics"], rows
PY
# The console table: a column per headline metric, a row per time step.
grep -q "eval.mIoU" "$D/batch.txt" || { cat "$D/batch.txt"; fail "no metric column in the table"; }
[ "$(grep -cE '^00000[01] +done' "$D/batch.txt")" = 2 ] || { cat "$D/batch.txt"; fail "rows"; }
echo "PASS in ${SECONDS}s"
