#!/usr/bin/env bash
# class_breakdown (bench/protocol) on two hand-written sweeps: per-class means, the paired
# difference, hit shares, the order, quoted class names and a run that did not finish.
#   class_breakdown_test.sh BUILD_DIR
set -uo pipefail
tool="$1/bench/protocol/class_breakdown"
[ -x "$tool" ] || { echo "no class_breakdown in $1"; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# sweep DIR STATUS_OF_RUN_2: two rooms (r1, r2), seed 0, and a third room r3
sweep() {
  mkdir -p "$tmp/$1"
  cat > "$tmp/$1/sweep.json" << EOF
{"runs": [{"dir": "runs/0000", "input": "r1", "seed": 0, "status": "ok"},
          {"dir": "runs/0001", "input": "r2", "seed": 0, "status": "ok"},
          {"dir": "runs/0002", "input": "r3", "seed": 0, "status": "$2"}]}
EOF
}
matches() {  # matches SWEEP RUN LINES...
  local dir="$tmp/$1/runs/$2/eval"
  mkdir -p "$dir"
  shift 2
  { echo "gt_label,class,matched_pred,iou"; printf '%s\n' "$@"; } > "$dir/matches.csv"
}
sweep a failed
sweep b ok
matches a 0000 "0,,0,0.9" '1,"table, instrument",4,0.8' "2,surgeon,5,0.4"
matches a 0001 "1,surgeon,2,0.6" "3,lamp,1,0.2"
matches b 0000 "0,,0,0.95" '1,"table, instrument",7,0.5' "2,surgeon,3,0.6"
matches b 0001 "1,surgeon,2,0.2" "3,lamp,8,0.3"
matches b 0002 "1,lamp,1,0.9"
"$tool" "$tmp/a" "$tmp/b" eval A B "$tmp/out" > "$tmp/out.txt" 2>&1 || fail "failed: $(cat "$tmp/out.txt")"
# lamp 20 vs 30 (-10); surgeon [40, 60] vs [60, 20]: means 50 / 40, difference +10, 95% interval
# +10 +- 12.706 * 42.43 / sqrt(2) = -371.2 .. +391.2, hits 50% / 50%; table 80 vs 50 (+30); all
# four instances 50 vs 40, differences [30, -20, 40, -10]: sd 29.44, +10 +- 3.182 * 29.44 / 2 =
# -36.8 .. +56.8. Ordered by the difference; label 0 and room r3 (failed in a) left out.
expected='| lamp | 1 | 20.0 | 30.0 | -10.0 (one instance) | 0% / 0% |
| surgeon | 2 | 50.0 | 40.0 | +10.0 (-371.2 to +391.2) | 50% / 50% |
| table, instrument | 1 | 80.0 | 50.0 | +30.0 (one instance) | 100% / 0% |
| all instances | 4 | 50.0 | 40.0 | +10.0 (-36.8 to +56.8) | 50% / 25% |'
got="$(grep '^| [a-z]' "$tmp/out.txt" | grep -v '^| class')"
[ "$got" = "$expected" ] || fail "table: $(cat "$tmp/out.txt")"
grep -q 'left out (not finished in both): a: r3 seed 0' "$tmp/out.txt" || fail "the failed run not named"
grep -q '"class": "table, instrument"' "$tmp/out.json" || fail "json lacks the quoted class"
grep -q 'A (blue) against B (grey)' "$tmp/out.svg" || fail "the chart does not name the methods"
# A --grid sweep: one point selected with @PARAM=VALUE; without it the rooms repeat, an error.
mkdir -p "$tmp/g"
cat > "$tmp/g/sweep.json" << EOF
{"runs": [{"dir": "runs/0000", "input": "r1", "seed": 0, "status": "ok", "params": {"k": "0"}},
          {"dir": "runs/0001", "input": "r1", "seed": 0, "status": "ok", "params": {"k": "1"}}]}
EOF
matches g 0000 "2,surgeon,5,0.1"
matches g 0001 "2,surgeon,5,0.9"
"$tool" "$tmp/g@k=1" "$tmp/b" eval A B "$tmp/out" > "$tmp/out.txt" 2>&1 || fail "grid point: $(cat "$tmp/out.txt")"
grep -q '^| surgeon | 1 | 90.0 | 60.0 | +30.0 (one instance) |' "$tmp/out.txt" || fail "grid point k=1: $(cat "$tmp/out.txt")"
if "$tool" "$tmp/g" "$tmp/b" eval A B "$tmp/out" > "$tmp/out.txt" 2>&1; then fail "a grid sweep without a point gave exit 0"; fi
grep -q 'select one with @PARAM=VALUE' "$tmp/out.txt" || fail "grid without a point: $(cat "$tmp/out.txt")"
if "$tool" "$tmp/g@k=7" "$tmp/b" eval A B "$tmp/out" > "$tmp/out.txt" 2>&1; then fail "no matching point gave exit 0"; fi
grep -q 'no run matches' "$tmp/out.txt" || fail "no matching point: $(cat "$tmp/out.txt")"
# A matches.csv written before eval named classes: a clear error, exit 1.
printf 'gt_label,matched_pred,iou\n1,4,0.8\n' > "$tmp/a/runs/0000/eval/matches.csv"
if "$tool" "$tmp/a" "$tmp/b" eval A B "$tmp/out" > "$tmp/out.txt" 2>&1; then fail "old matches.csv gave exit 0"; fi
grep -q 'has no column class' "$tmp/out.txt" || fail "old matches.csv: $(cat "$tmp/out.txt")"
echo "$failures problems"
[ "$failures" -eq 0 ]
