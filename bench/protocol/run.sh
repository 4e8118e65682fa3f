#!/usr/bin/env bash
# Runs a table of sweeps, one `gslift sweep` per line, then protocol_chart writes the table's
# results: bench/results/<table name>.{json,svg} (per line a dev and a test bar, and the paired
# comparisons of the pairs.tsv beside the table). The default table is the dev/test protocol
# (issue 28, protocol.tsv: a line per method and set); each method's ablations are a table of the
# same columns in its own folder (bench/langor/langor.tsv, bench/saga/saga.tsv, ...).
#   bench/protocol/run.sh [--table TSV] [--dry-run] [--inputs SET] [--extra 'ARGS']
#                         [--results DIR] [NAME[/SET]]...   (default: every line)
# e.g. bench/protocol/run.sh langor/test protosaga gaga
#      bench/protocol/run.sh --table bench/langor/langor.tsv
# --dry-run: each line's `gslift sweep --dry-run` (every graph, --set and capture validated, nothing
# runs, no chart): the check a table's test makes. --inputs replaces the capture set of every line
# that has one, --extra adds sweep arguments to every line: a smoke of a table is
#   PROTOCOL_DIR=/tmp/smoke bench/protocol/run.sh --table T --inputs ONE_ROOM.txt \
#     --extra '--set recon.iterations=20' --results /tmp/smoke
# $GSLIFT is the gslift executable (default ./build/gslift).
# Sweep folders go to $PROTOCOL_DIR (default build/<table name>), one per line; a finished one
# (its .done) is not redone: delete the folder to redo it. A line with no sweep folder here keeps
# the result the results file already holds for it, so some lines can be refreshed on a machine
# that does not have the others' sweeps. Each sweep runs without the stage cache, so every run's
# time is a cold run's, unless its line names one (`--cache-dir`). About 1-2 minutes per room on
# 2 cores: the 20 test rooms of one method take 20-40 minutes.
set -euo pipefail
cd "$(dirname "$0")/../.."
table=bench/protocol/protocol.tsv
dry_run=""
inputs_override=""
extra_all=""
results=bench/results
selection=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --table) table="$2"; shift 2 ;;
    --dry-run) dry_run=1; shift ;;
    --inputs) inputs_override="$2"; shift 2 ;;
    --extra) extra_all="$2"; shift 2 ;;
    --results) results="$2"; shift 2 ;;
    -*) echo "run.sh: unknown option $1" >&2; exit 2 ;;
    *) selection+=("$1"); shift ;;
  esac
done
[[ -f "$table" ]] || { echo "run.sh: no table $table" >&2; exit 2; }
stem=$(basename "$table" .tsv)
out="${PROTOCOL_DIR:-build/$stem}"
gslift="${GSLIFT:-./build/gslift}"  # the tests' build may be elsewhere
[[ -n "$dry_run" ]] || mkdir -p "$out"
wanted() {  # wanted NAME SET: is this line asked for
  [[ ${#selection[@]} -eq 0 ]] && return 0
  local s
  for s in "${selection[@]}"; do
    [[ "$s" == "$1" || "$s" == "$1/$2" ]] && return 0
  done
  return 1
}
failed=0
while IFS=$'\t' read -r method set graph _ inputs extra; do
  [[ -z "$method" || "$method" == \#* ]] && continue
  wanted "$method" "$set" || continue
  name="${method}_${set}"
  args=()
  if [[ "$inputs" != "-" ]]; then
    inputs="${inputs_override:-$inputs}"
    args+=(--inputs "$inputs")
  fi
  # shellcheck disable=SC2206  # the further arguments are words, as written in the table
  [[ -n "${extra:-}" ]] && args+=($extra)
  # shellcheck disable=SC2206
  [[ -n "$extra_all" ]] && args+=($extra_all)
  if [[ -n "$dry_run" ]]; then
    echo "$stem: $name ($graph)" >&2
    "$gslift" sweep "$graph" "${args[@]}" --log-level warn --dry-run || failed=1
    continue
  fi
  [[ -f "$out/$name/.done" ]] && { echo "$stem: $name done already" >&2; continue; }
  rm -rf "${out:?}/$name"
  echo "$stem: $name ($graph over $inputs)" >&2
  # Cold runs, unless the line names a stage cache: a line that runs each room many times (a
  # --grid over prompt.only) would otherwise rebuild the reconstruction for every run.
  cache=(--no-cache)
  [[ " ${args[*]} " == *" --cache-dir "* ]] && cache=()
  "$gslift" sweep "$graph" "${args[@]}" "${cache[@]}" --threads 2 --log-level warn \
    --out "$out/$name" > "$out/$name.txt" || true
  touch "$out/$name/.done"
done < "$table"
[[ -n "$dry_run" ]] && exit "$failed"
mkdir -p "$results"
./build/bench/protocol/protocol_chart "$out" "$table" "$results"
