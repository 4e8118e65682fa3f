#!/usr/bin/env bash
# The stability matrix (issue 15): every method of bench/experiments/methods.tsv x every failure
# knob of bench/stability/knobs.tsv that touches an input the method uses x its levels x seeds, on
# the embedded OR at 240x180 with the methods' shortened settings (methods.tsv), one `gslift sweep`
# per method over the capture specs. Then stability_matrix writes bench/results/stability.json,
# stability.md and one heat map SVG per method.
#   bench/stability/run.sh [SEEDS] [METHOD...]      (default seeds 0,1,2; all methods)
# Sweep folders go to $STABILITY_DIR (default build/stability); runs are not cached (every capture
# differs) and run at low priority. A run that crashes or ends with an error is counted.
# KNOBS=drapes,views runs only those knobs, into <method>@drapes+views beside the full sweep
# <method>: stability_matrix reads every sweep of a method, so a knob added later is run alone.
set -euo pipefail
cd "$(dirname "$0")/../.."
seeds="${1:-0,1,2}"
shift || true
out="${STABILITY_DIR:-build/stability}"
only="${KNOBS:-}"
gslift=./build/gslift
mkdir -p "$out"
IFS=',' read -r -a seed_list <<< "$seeds"
while IFS=$'\t' read -r name graph headline inputs settings; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  if [[ $# -gt 0 && ! " $* " =~ " $name " ]]; then continue; fi
  specs=()
  while IFS=$'\t' read -r knob group levels; do
    [[ -z "$knob" || "$knob" == \#* ]] && continue
    [[ ",$inputs," == *",$group,"* ]] || continue
    [[ -z "$only" || ",$only," == *",$knob,"* ]] || continue
    IFS=',' read -r -a level_list <<< "$levels"
    for level in "${level_list[@]}"; do
      for seed in "${seed_list[@]}"; do
        specs+=("embedded:or?seed=$seed&width=240&height=180&$knob=$level")
      done
    done
  done < bench/stability/knobs.tsv
  grid="input=$(IFS=','; echo "${specs[*]}")"
  sets=()
  for s in $settings; do sets+=(--set "$s"); done
  [[ ${#specs[@]} -eq 0 ]] && continue
  folder="$name${only:+@${only//,/+}}"
  echo "stability: $folder, ${#specs[@]} runs" >&2
  nice -n 19 "$gslift" sweep "$graph" --grid "$grid" "${sets[@]}" --no-cache --threads 2 \
    --log-level warn --out "$out/$folder" > "$out/$folder.txt" || true
done < bench/experiments/methods.tsv
./build/bench/stability/stability_matrix "$out" bench/experiments/methods.tsv \
  bench/stability/knobs.tsv bench/results
