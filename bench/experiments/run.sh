#!/usr/bin/env bash
# The experiment layer's benchmark (issue 15): every method of methods.tsv at its defaults, every
# budget axis of budgets.tsv and every variant of variants.tsv, as `gslift sweep`s over seeds on
# the embedded OR (each seed its own room: --input 'embedded:or?seed={seed}'), through one stage
# cache; then experiments_chart draws the speed-accuracy chart (and against peak memory) with
# Pareto fronts, the budget curves with their knees, and writes bench/results/experiments.json.
#   bench/experiments/run.sh [SEEDS]          (default 0-2)
# Sweep folders and the cache go to $EXPERIMENTS_DIR (default build/experiments). A node loaded
# from the cache is charged the wall time it took where it ran (run.json's cache_key), so every
# point's time is a cold run's.
set -euo pipefail
cd "$(dirname "$0")/../.."
seeds="${1:-0-2}"
out="${EXPERIMENTS_DIR:-build/experiments}"
gslift=./build/gslift
mkdir -p "$out"
sweep() {  # sweep NAME GRAPH PARAM VALUES
  local name="$1" graph="$2" param="$3" values="$4"
  # A finished sweep is not redone when the script is run again (delete its folder to redo it).
  [[ -f "$out/$name/.done" ]] && { echo "experiments: $name done already" >&2; return; }
  echo "experiments: $name ($param=$values)" >&2
  # --input would override a grid over the graph's input param (the capture resolution axis).
  local input=(--input 'embedded:or?seed={seed}')
  [[ "$param" == input ]] && input=()
  "$gslift" sweep "$graph" --grid "$param=$values" --seeds "$seeds" \
    "${input[@]}" --cache-dir "$out/cache" --cache-size 60 --threads 2 \
    --log-level warn --out "$out/$name" > "$out/$name.txt" || true
  touch "$out/$name/.done"
}
while IFS=$'\t' read -r name graph headline inputs settings; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  sweep "method_$name" "$graph" input 'embedded:or?seed={seed}'  # the graph as it is
done < bench/experiments/methods.tsv
while IFS=$'\t' read -r method param values; do
  [[ -z "$method" || "$method" == \#* ]] && continue
  graph=$(awk -F'\t' -v m="$method" '$1 == m {print $2}' bench/experiments/methods.tsv)
  sweep "budget_${method}_${param//./_}" "$graph" "$param" "$values"
done < bench/experiments/budgets.tsv
while IFS=$'\t' read -r method name graph; do
  [[ -z "$method" || "$method" == \#* ]] && continue
  sweep "variant_${method}_$name" "$graph" input 'embedded:or?seed={seed}'
done < bench/experiments/variants.tsv
./build/bench/experiments/experiments_chart "$out" bench/experiments bench/results
