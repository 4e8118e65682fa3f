#!/usr/bin/env bash
# binary_compare_chart (bench/splat_recon/compare_binaries.sh's chart) on hand-written runs:
# medians, their ratio, the models' identity and a failed run.
#   binary_compare_chart_test.sh BUILD_DIR
set -uo pipefail
chart="$1/bench/splat_recon/binary_compare_chart"
[ -x "$chart" ] || { echo "no binary_compare_chart in $1"; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# run DIR WALL BACKWARD MODEL: a finished run's run.json and its reconstruction's model.ply
run() {
  mkdir -p "$tmp/w/$1/recon"
  printf '%s' "$4" > "$tmp/w/$1/recon/model.ply"
  cat > "$tmp/w/$1/run.json" << EOF
{"gslift": {"git": "abc"}, "run": {"status": "ok", "total_s": $2, "peak_rss_mb": 500},
 "nodes": [{"id": "recon", "type": "splat.reconstruct", "wall_s": $2,
            "records": {"backward_seconds": $3, "render_seconds": 1}}]}
EOF
}
mkdir -p "$tmp/w"
printf 'labels\tbefore,after\ngraph\tg.yaml\nmachine\tthe test\n' > "$tmp/w/setup.tsv"
run old-1 10 4 same; run new-1 6 2 same
run old-2 14 6 same; run new-2 9 3 same
run old-3 12 5 same; run new-3 7 1 same
"$chart" "$tmp/w" "$tmp/r" t > "$tmp/out.txt" 2>&1 || fail "chart failed: $(cat "$tmp/out.txt")"
# Medians: old 12, new 7 -> 0.58x; backward 5 -> 2 -> 0.40x.
grep -q '^whole run (s): 12.0 -> 7.0 (0.58x)$' "$tmp/out.txt" || fail "wall medians: $(cat "$tmp/out.txt")"
grep -q '^  backward (s): 5.0 -> 2.0 (0.40x)$' "$tmp/out.txt" || fail "backward medians"
grep -q '"identical_models": true' "$tmp/r/t.json" || fail "identical models not seen"
grep -q 'grey before, blue after' "$tmp/r/t.svg" || fail "the chart does not name the binaries"
# A model that differs, and a run that did not finish: recorded, exit 1.
run new-3 7 1 other
rm "$tmp/w/old-2/run.json"
if "$chart" "$tmp/w" "$tmp/r" t > "$tmp/out.txt" 2>&1; then fail "a failed run gave exit 0"; fi
grep -q '"identical_models": false' "$tmp/r/t.json" || fail "a different model not seen"
grep -q '"old-2"' "$tmp/r/t.json" || fail "the failed run is not listed"
grep -q '^whole run (s): 11.0 -> 7.0 (0.64x)$' "$tmp/out.txt" || fail "medians without the failed run"
# bench_dtu_compare runs (compare_binaries.sh --dtu): per resolution the seconds per step, and
# the decoding and the steps alone where a binary reports its phases (the old one does not here).
# dtu DIR STEP_S SECONDS PREPARE_S: one 100-step run at 397x298 (PREPARE_S empty: no phases).
dtu() {
  mkdir -p "$tmp/d/$1"
  local phases=""
  [ -n "$4" ] && phases="\"phases\": {\"prepare\": $4},"
  cat > "$tmp/d/$1/dtu_compare.json" << EOF
{"runs": [{"resolution": [397, 298], "steps": 100, "seconds": $3, "seconds_per_step": $2,
           $phases "test_psnr": 15.92}]}
EOF
}
mkdir -p "$tmp/d"
printf 'labels\tbefore,after\ngraph\tDTU\nmachine\tthe test\n' > "$tmp/d/setup.tsv"
dtu old-1 0.050 5.0 ""; dtu new-1 0.030 3.0 1.0
dtu old-2 0.060 6.0 ""; dtu new-2 0.032 3.2 1.2
dtu old-3 0.055 5.5 ""; dtu new-3 0.034 3.4 1.1
"$chart" "$tmp/d" "$tmp/r" dt > "$tmp/out.txt" 2>&1 || fail "DTU chart failed: $(cat "$tmp/out.txt")"
# Medians 55 -> 32 ms per step: 0.582x. The new binary's steps alone (3.2 - 1.1 s over 100
# steps, 21 ms) have no counterpart in the old runs: no row for them.
grep -q '^397x298: per step (ms): 55.00 -> 32.00 (0.582x)$' "$tmp/out.txt" ||
  fail "DTU medians: $(cat "$tmp/out.txt")"
if grep -q 'steps alone' "$tmp/out.txt"; then fail "a phase only one binary reports was compared"; fi
grep -q '"identical_psnr": true' "$tmp/r/dt.json" || fail "equal PSNRs not seen"
grep -q 'PSNR 15.9200 -&gt; 15.9200' "$tmp/r/dt.svg" || fail "the chart does not give the PSNRs"
echo "$failures problems"
[ "$failures" -eq 0 ]
