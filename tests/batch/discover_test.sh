#!/usr/bin/env bash
# discover_test.sh GSLIFT: the nightly case without a scheduler (issue 16). `gslift batch
# --discover DIR` over tiny embedded-OR captures written by `gslift synth`: the first night
# processes both captures; a capture being copied in under a dot-name is left alone; the second
# night, after it is renamed into place and one more arrives, processes exactly those two and
# leaves the first night's results untouched; a third night with nothing new runs nothing.
set -euo pipefail
GSLIFT=$(realpath "$1")
HERE=$(cd "$(dirname "$0")" && pwd)
fail() { echo "FAIL: $*"; exit 1; }
D=$(mktemp -d /tmp/gslift_discover_XXXXXX)
# A stage cache of its own: never the user's, never one left by an earlier test run.
export GSLIFT_STAGE_CACHE="$D/stage-cache"
trap '[ -n "${GSLIFT_KEEP_SCRATCH:-}" ] && echo "kept $D" || rm -rf "$D"' EXIT
synth() { "$GSLIFT" synth --out "$1" --seed "$2" --views 4 --width 64 --height 48 --log-level warn >/dev/null; }
night() {
  "$GSLIFT" batch --discover "$D/in" "$HERE/tiny.yaml" --out "$D/out" --threads 1 >"$D/night.txt" 2>&1 ||
    { cat "$D/night.txt"; fail "gslift batch --discover failed"; }
}
statuses() { python3 -c 'import json,sys; print(" ".join(c["name"] + ":" + c["status"] for c in json.load(open(sys.argv[1]))["captures"]))' "$D/out/_summary.json"; }

synth "$D/in/or_mon_1" 0
synth "$D/in/or_mon_2" 1
synth "$D/in/.or_tue_1" 2  # still being copied
night
[ "$(statuses)" = "or_mon_1:done or_mon_2:done" ] || fail "first night: $(statuses)"
[ ! -e "$D/out/.or_tue_1" ] && [ ! -e "$D/out/or_tue_1" ] || fail "a dot-named capture was processed"
first=$(stat -c %y "$D/out/or_mon_1/_DONE")

mv "$D/in/.or_tue_1" "$D/in/or_tue_1"
synth "$D/in/or_tue_2" 3
night
[ "$(statuses)" = "or_tue_1:done or_tue_2:done" ] || fail "second night: $(statuses)"
[ "$(stat -c %y "$D/out/or_mon_1/_DONE")" = "$first" ] || fail "the first night's capture was redone"

night
[ "$(statuses)" = "" ] || fail "third night: $(statuses)"
grep -q "discovered 0 capture(s)" "$D/night.txt" || fail "third night: $(cat "$D/night.txt")"
python3 "$HERE/check_outputs.py" batch "$D/out" >/dev/null || fail "incomplete files"
echo "PASS in ${SECONDS}s"
