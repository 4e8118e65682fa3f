#!/usr/bin/env bash
# The benchmark tables (bench/protocol/run.sh's: the dev/test protocol and each method's
# ablations) check themselves without running anything:
#   - every line passes `gslift sweep --dry-run` (its graph and --set values validated on one
#     room), through run.sh itself, so the runner's reading of the table is tested too, and every
#     capture set the tables name passes it once (each room checked as `gslift validate --input`);
#   - every line's name and set are unique in its table, and every row of the pairs.tsv beside a
#     table names two of its lines on that set (protocol_chart would skip a row that does not);
#   - a table with a misspelt param is refused (the test of this test).
# Lines on DTU scan 24 (../shared/data/dtu_scan24) are left out when the data is absent.
#
# usage: bench_tables_test.sh GSLIFT REPO_ROOT
set -u
export GSLIFT
GSLIFT=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
src=$(cd "$2" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() {
  echo "FAIL $*"
  failures=$((failures + 1))
}
tables=(bench/protocol/protocol.tsv bench/langor/langor.tsv bench/saga/saga.tsv
  bench/protosaga/protosaga.tsv bench/detector_fusion/detector_fusion.tsv)
have_dtu=1
declare -A set_checked
echo "embedded:or?seed=0" > "$tmp/one_room.txt"
[ -d "$src/../shared/data/dtu_scan24" ] || have_dtu=""
for t in "${tables[@]}"; do
  [ -f "$src/$t" ] || { fail "$t does not exist"; continue; }
  # Unique names per set; the pairs name lines of the table.
  dup=$(awk -F'\t' '!/^#/ && NF >= 5 {print $1 "/" $2}' "$src/$t" | sort | uniq -d)
  [ -z "$dup" ] || fail "$t: lines named twice: $dup"
  pairs="$(dirname "$src/$t")/pairs.tsv"
  if [ -f "$pairs" ]; then
    while IFS=$'\t' read -r first second set; do
      [[ -z "$first" || "$first" == \#* ]] && continue
      for name in "$first" "$second"; do
        awk -F'\t' -v n="$name" -v s="$set" '$1 == n && $2 == s {found = 1} END {exit !found}' \
          "$src/$t" || fail "$pairs: '$name' on '$set' is no line of $t"
      done
    done < "$pairs"
  fi
  # The dry run of every line on one room (its graph and --set values; DTU lines only with the
  # data here), then of each capture set once: every room of a set is checked the same way for
  # every line, and a gslift start costs about 0.4 s.
  names=()
  while IFS=$'\t' read -r name set graph _ inputs _; do
    [[ -z "$name" || "$name" == \#* ]] && continue
    if [ -z "$have_dtu" ] && grep -q "dtu" <<< "$graph"; then continue; fi
    names+=("$name/$set")
    if [[ "$inputs" != "-" && -z "${set_checked[$inputs]:-}" ]]; then
      set_checked[$inputs]=1
      (cd "$src" && "$GSLIFT" sweep "$graph" --inputs "$inputs" --dry-run > "$tmp/set.out" 2>&1) ||
        { fail "$t: the capture set $inputs does not pass:"; sed 's|^|    |' "$tmp/set.out"; }
    fi
  done < "$src/$t"
  if ! out=$("$src/bench/protocol/run.sh" --table "$t" --inputs "$tmp/one_room.txt" --dry-run \
    "${names[@]}" 2>&1); then
    fail "$t: a line does not pass gslift sweep --dry-run:"
    printf '%s\n' "$out" | sed 's|^|    |'
  fi
  runs=$(grep -c "every combination valid" <<< "$out")
  [ "$runs" -eq "${#names[@]}" ] || fail "$t: ${#names[@]} lines, $runs dry runs passed"
done
# A misspelt param in a table is refused.
printf 'bad\tdev\tgraphs/langor.yaml\teval.mIoU\tbench/sets/or_dev.txt\t--set lift.sigmaa=0.7\n' \
  > "$tmp/bad.tsv"
if "$src/bench/protocol/run.sh" --table "$tmp/bad.tsv" --dry-run > "$tmp/bad.out" 2>&1; then
  fail "a table with a misspelt param passed its dry run"
elif ! grep -q "sigmaa" "$tmp/bad.out"; then
  fail "the misspelt table's error does not name the param:"
  sed 's|^|    |' "$tmp/bad.out"
fi
# protocol_chart reads a line's sweep where it is here (a room run several times scored by the
# mean of its runs), and keeps the stored result of a line whose sweep is not (a refresh of some
# lines on a machine without the others' sweeps).
chart="$(dirname "$GSLIFT")/bench/protocol/protocol_chart"
if [ -x "$chart" ]; then
  c="$tmp/chart"
  mkdir -p "$c/sweeps/a_dev" "$c/results"
  printf 'a\tdev\tg.yaml\teval.mIoU\ts.txt\nb\tdev\tg.yaml\teval.mIoU\ts.txt\n' > "$c/t.tsv"
  cat > "$c/sweeps/a_dev/sweep.json" << 'EOF'
{"runs": [
  {"status": "ok", "input": "r1", "seed": 0, "metrics": {"eval.mIoU": 40}, "total_s": 10,
   "peak_rss_mb": 100},
  {"status": "ok", "input": "r2", "seed": 0, "metrics": {"eval.mIoU": 60}, "total_s": 12,
   "peak_rss_mb": 100},
  {"status": "ok", "input": "r1", "seed": 0, "metrics": {"eval.mIoU": 20}, "total_s": 10,
   "peak_rss_mb": 100}]}
EOF
  cat > "$c/results/t.json" << 'EOF'
{"sets": [
  {"method": "a", "set": "dev", "graph": "g.yaml", "headline": "eval.mIoU", "failed": 0,
   "errors": [], "rooms": [{"input": "r1", "seed": 0, "value": 1}], "others": {}, "records": {},
   "median_node_s": {}, "median_time_s": 5, "median_peak_mb": 50},
  {"method": "b", "set": "dev", "graph": "g.yaml", "headline": "eval.mIoU", "failed": 0,
   "errors": [], "rooms": [{"input": "r1", "seed": 0, "value": 30},
   {"input": "r2", "seed": 0, "value": 36}], "others": {}, "records": {"eval.mIoU": 33},
   "median_node_s": {"recon": 7}, "median_time_s": 8, "median_peak_mb": 50}]}
EOF
  "$chart" "$c/sweeps" "$c/t.tsv" "$c/results" > "$c/out.txt" 2>&1 || fail "protocol_chart failed"
  # Room r1 ran twice (a --grid line): its value is their mean, 30; the line's mean (30 + 60) / 2.
  grep -q '^| a | dev | 2 | eval.mIoU | 45.0 ' "$c/out.txt" ||
    fail "protocol_chart did not read line a from its sweep: $(cat "$c/out.txt")"
  grep -q '^| b | dev | 2 | eval.mIoU | 33.0 .* | 8 s |$' "$c/out.txt" ||
    fail "protocol_chart did not keep line b's stored result: $(cat "$c/out.txt")"
else
  fail "no protocol_chart next to $GSLIFT"
fi
echo "${#tables[@]} tables, $failures problems"
[ "$failures" -eq 0 ]
