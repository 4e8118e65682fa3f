#!/usr/bin/env bash
# The scale test (issue 29): every capture of bench/sets/scale.txt reconstructed by
# graphs/examples/reconstruct.yaml at 100, 500 and 2000 steps, one `gslift sweep`. Held-out PSNR
# must not fall as steps grow, and the embedded OR must reconstruct alike in any units.
# Writes bench/results/scale.{json,csv,svg}.
#   bench/scale/run.sh [SWEEP_DIR]     (default build/scale_bench; a finished sweep is reused)
set -euo pipefail
cd "$(dirname "$0")/../.."
out="${1:-build/scale_bench}"
if [[ ! -f "$out/results.csv" ]] || grep -q ',failed,' "$out/results.csv" ||
  [[ $(($(wc -l <"$out/results.csv") - 1)) -lt 15 ]]; then
  ./build/gslift sweep graphs/examples/reconstruct.yaml --inputs bench/sets/scale.txt \
    --grid recon.iterations=100,500,2000 --out "$out" --no-cache --log-level warn
fi
python3 bench/scale/chart.py "$out/results.csv" bench/results/scale "$(./build/gslift --version)" \
  "$(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p')"
