#!/usr/bin/env bash
# The dev/test protocol (issue 28): every line of protocol.tsv as one `gslift sweep` over its
# capture set, then protocol_chart writes bench/results/protocol.{json,svg} (dev and test side by
# side per method, and the paired comparisons of pairs.tsv).
#   bench/protocol/run.sh [METHOD[/SET]]...   (default: every line)
# e.g. bench/protocol/run.sh langor/test protosaga gaga
# Sweep folders go to $PROTOCOL_DIR (default build/protocol), one per method and set; a finished
# one (its .done) is not redone: delete the folder to redo it. Each sweep runs without the stage
# cache, so every run's time is a cold run's. About 1-2 minutes per room on 2 cores: the 20 test
# rooms of one method take 20-40 minutes.
set -euo pipefail
cd "$(dirname "$0")/../.."
out="${PROTOCOL_DIR:-build/protocol}"
gslift=./build/gslift
mkdir -p "$out"
wanted() {  # wanted METHOD SET: is this line asked for
  [[ ${#selection[@]} -eq 0 ]] && return 0
  local s
  for s in "${selection[@]}"; do
    [[ "$s" == "$1" || "$s" == "$1/$2" ]] && return 0
  done
  return 1
}
selection=("$@")
while IFS=$'\t' read -r method set graph headline inputs extra; do
  [[ -z "$method" || "$method" == \#* ]] && continue
  wanted "$method" "$set" || continue
  name="${method}_${set}"
  [[ -f "$out/$name/.done" ]] && { echo "protocol: $name done already" >&2; continue; }
  rm -rf "${out:?}/$name"
  args=()
  [[ "$inputs" != "-" ]] && args+=(--inputs "$inputs")
  # shellcheck disable=SC2206  # the further arguments are words, as written in the table
  [[ -n "${extra:-}" ]] && args+=($extra)
  echo "protocol: $name ($graph over ${inputs})" >&2
  "$gslift" sweep "$graph" "${args[@]}" --no-cache --threads 2 --log-level warn \
    --out "$out/$name" > "$out/$name.txt" || true
  touch "$out/$name/.done"
done < bench/protocol/protocol.tsv
./build/bench/protocol/protocol_chart "$out" bench/protocol bench/results
