#!/usr/bin/env bash
# Builds the seed corpus of every fuzz target (fuzz/targets.cpp) into SEEDS_DIR/<target>/ from
# the project's own files (tests/data, graphs/) and the binary seeds fuzz_make_seeds writes with
# gslift's writers; nothing is committed twice. Usage: fuzz/make_seeds.sh BUILD_FUZZ_DIR SEEDS_DIR
set -euo pipefail
build=${1:?usage: fuzz/make_seeds.sh BUILD_FUZZ_DIR SEEDS_DIR}
out=${2:?usage: fuzz/make_seeds.sh BUILD_FUZZ_DIR SEEDS_DIR}
src=$(cd "$(dirname "$0")/.." && pwd)
split=$'\n#GSLIFT-FUZZ-FILE#\n'  # fuzz_support.hpp kSplit: one input, several files

rm -rf "$out"
mkdir -p "$out"/{graph_yaml,capture_yaml,colmap_text,colmap_binary,transforms_json,vlm_reply,coco_rle,mask_png,depth_image,ply}
"$build/fuzz/fuzz_make_seeds" "$out"

# Graph YAML: the shipped graphs and the extends fixtures, plus one that extends and substitutes.
i=0
for f in "$src"/graphs/*.yaml "$src"/graphs/examples/*.yaml "$src"/tests/data/graphs/*.yaml \
         "$src"/tests/data/graphs/variants/*.yaml; do
  [ -f "$f" ] && cp "$f" "$out/graph_yaml/$((i++))_$(basename "$f")"
done
cat > "$out/graph_yaml/extends_subst.yaml" <<'YAML'
extends: leaf.yaml
graph: fuzz
params: {input: "x", scale: 3.5, seed: 1}
nodes:
  a: {type: debug.constant, params: {value: "${scale}"}}
  b: {type: debug.add, in: {a: a.out, b: a.out}}
YAML

cat > "$out/capture_yaml/full.yaml" <<'YAML'
format: gslift.capture/v1
name: small
model: sparse/0
images: images
depth: {folder: depth, scale: 1000}
held_out: [cam_01]
vlm: {folder: vlm, rounds: 3, coords: resized_abs, input_size: [640, 480]}
sam_box: sam_box
sam_auto: sam_auto
gt: gt
YAML

d="$src/tests/data/ingest/colmap_text"
{ cat "$d/cameras.txt"; printf '%s' "$split"; cat "$d/images.txt"; printf '%s' "$split"; cat "$d/points3D.txt"; } \
  > "$out/colmap_text/fixture.txt"

cat > "$out/transforms_json/frames.json" <<'JSON'
{"camera_angle_x": 0.69, "w": 8, "h": 6, "k1": 0.01, "camera_model": "OPENCV",
 "frames": [{"file_path": "./images/r_0", "transform_matrix": [[1,0,0,0.5],[0,1,0,0],[0,0,1,2],[0,0,0,1]]},
            {"file_path": "images/r_0.png", "fl_x": 9, "cx": 4, "depth_file_path": "images/r_0.png",
             "transform_matrix": [[1,0,0,0],[0,0,-1,0],[0,1,0,1]]}]}
JSON

cat > "$out/vlm_reply/json_list.txt" <<'TXT'
```json
[
  {"bbox_2d": [100, 200, 500, 600], "label": "surgeon"},
  {"bbox_2d": [300, 300, 300, 400], "label": "line"},
  {"bbox": [900, 900, 1200, 1000], "label": "lamp", "score": 0.5}
]
```
TXT
printf '%s' '{"bbox_2d": [1, 2, 30, 40], "label": "table"}' > "$out/vlm_reply/one_object.txt"
{ printf '%s' '[{"bbox_2d": [0, 0, 10, 10], "label": "a"}]'; printf '%s' "$split"; printf '%s' 'no boxes here'; } \
  > "$out/vlm_reply/two_rounds.txt"

cp "$src/tests/data/splat/inria_degree1.ply" "$out/ply/"
echo "seeds: $(find "$out" -type f | wc -l) files in $out"
