#!/usr/bin/env bash
# LangOR on the embedded OR read through the OR rig reader against the same room in gslift's own
# layout (issue 29, docs/or-rig.md): `gslift synth` writes capture seed S both ways, and
# graphs/langor.yaml runs on each. The rig layout differs in what the reader has to undo: colour
# through a rational distortion (undistorted and cropped on load), depth from a camera of its own
# resolution and viewpoint (registered to colour on load). Writes bench/results/rig_langor.json.
#   bench/rig/langor_rig_compare.sh [SEED]          (default 0)
# Runs go to $RIG_BENCH_DIR (default build/rig_bench), without the stage cache.
set -euo pipefail
cd "$(dirname "$0")/../.."
seed="${1:-0}"
out="${RIG_BENCH_DIR:-build/rig_bench}"
gslift=./build/gslift
rm -rf "$out"
mkdir -p "$out"
"$gslift" synth --out "$out/own" --seed "$seed" >/dev/null
"$gslift" synth --out "$out/rig" --seed "$seed" --layout rig >/dev/null
for layout in own rig; do
  input="$out/own"
  [[ $layout == rig ]] && input="$out/rig/000000"
  start=$SECONDS
  "$gslift" run graphs/langor.yaml --input "$input" --out "$out/run_$layout" --no-cache \
    --log-level warn >"$out/run_$layout.txt" 2>&1 || { cat "$out/run_$layout.txt"; exit 1; }
  echo "$layout: $((SECONDS - start)) s"
done
python3 - "$out" "$seed" <<'PY'
import json, sys
out, seed = sys.argv[1], int(sys.argv[2])
def metrics(layout):
    run = json.load(open(f"{out}/run_{layout}/run.json"))
    for n in run["nodes"]:
        if n["id"] == "eval":
            r = n["records"]
            return {k: r[k] for k in ("mIoU", "mLocAcc", "mAcc") if k in r} | {"total_s": run["run"]["total_s"]}
    raise SystemExit(f"no eval node in {out}/run_{layout}/run.json")
result = {"seed": seed, "graph": "graphs/langor.yaml", "gslift_layout": metrics("own"),
          "rig_layout": metrics("rig")}
result["mIoU_difference"] = result["rig_layout"]["mIoU"] - result["gslift_layout"]["mIoU"]
json.dump(result, open("bench/results/rig_langor.json", "w"), indent=2)
print(json.dumps(result, indent=2))
PY
