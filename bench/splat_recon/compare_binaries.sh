#!/usr/bin/env bash
# One graph run by two gslift binaries on one machine, alternated (old, new, old, new, ...) so
# that the machine's drift hits both alike (issue 31's speed targets are ratios to an older
# binary): each run `gslift run GRAPH --no-cache --threads 2`, then binary_compare_chart writes
# bench/results/<name>.{json,svg}: per binary the medians of the run's wall time, its peak
# memory and the reconstruction's phases, their ratios new/old, each round's values, the machine,
# and whether every run wrote the same model.ply.
#   bench/splat_recon/compare_binaries.sh OLD_GSLIFT NEW_GSLIFT [--rounds 3]
#       [--graph graphs/langor.yaml] [--name main_job_binaries] [--results DIR]
#       [--labels OLD,NEW]   (what the chart calls them, e.g. their commits; default old,new)
# With --dtu the two binaries are bench_dtu_compare builds instead, each run
# `bench_dtu_compare --steps 100 --large 1 --variants rms:0.5:crop` on ../shared/data/dtu_scan24
# (issue 31's DTU target), and the chart compares the seconds per step at 400x300 and 800x600 (the
# bench's measure: the reconstruction's time, decoding the photos included, over its steps),
# the decoding (`prepare`) and the steps alone where both binaries report their phases.
# An older binary: build a commit in a worktree (git worktree add /tmp/old COMMIT; cmake -S
# /tmp/old -B /tmp/old/build ...; cmake --build /tmp/old/build --target gslift). Runs go to
# $COMPARE_DIR (default build/<name>), which is emptied first. The main job takes 1-2.5 minutes
# a run on 2 cores: three rounds about 10 minutes.
set -euo pipefail
cd "$(dirname "$0")/../.."
[[ $# -ge 2 ]] || { sed -n 2,19p "$0" >&2; exit 2; }
old="$1"
new="$2"
shift 2
rounds=3
graph=graphs/langor.yaml
name=
results=bench/results
labels=old,new
dtu=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --dtu) dtu=../shared/data/dtu_scan24; shift ;;
    --rounds) rounds="$2"; shift 2 ;;
    --graph) graph="$2"; shift 2 ;;
    --name) name="$2"; shift 2 ;;
    --results) results="$2"; shift 2 ;;
    --labels) labels="$2"; shift 2 ;;
    *) echo "compare_binaries.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
for b in "$old" "$new"; do
  [[ -x "$b" ]] || { echo "compare_binaries.sh: $b is not an executable" >&2; exit 2; }
done
if [[ -n "$dtu" ]]; then
  name="${name:-dtu_binaries}"
  graph="DTU scan24, 100 steps"
  [[ -d "$dtu" ]] || { echo "compare_binaries.sh: $dtu not found (../shared beside the checkout)" >&2; exit 4; }
else
  name="${name:-main_job_binaries}"
  "$new" validate "$graph" > /dev/null
fi
work="${COMPARE_DIR:-build/$name}"
rm -rf "${work:?}"
mkdir -p "$work"
{
  echo "old	$(realpath "$old")"
  echo "new	$(realpath "$new")"
  echo "labels	$labels"
  echo "graph	$graph"
  echo "machine	$(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores, $(grep -q avx512f /proc/cpuinfo && echo AVX-512 || echo 'AVX2, no AVX-512')"
} > "$work/setup.tsv"
for ((r = 1; r <= rounds; ++r)); do
  for which in old new; do
    bin="$old"
    [[ "$which" == new ]] && bin="$new"
    echo "compare_binaries: round $r, $which" >&2
    if [[ -n "$dtu" ]]; then
      "$bin" --dtu "$dtu" --steps 100 --large 1 --variants rms:0.5:crop --out "$work/$which-$r" \
        > "$work/$which-$r.txt" 2>&1 || echo "compare_binaries: $which-$r failed" >&2
    else
      "$bin" run "$graph" --no-cache --threads 2 --log-level warn --out "$work/$which-$r" \
        > "$work/$which-$r.txt" 2>&1 || echo "compare_binaries: $which-$r failed" >&2
    fi
  done
done
./build/bench/splat_recon/binary_compare_chart "$work" "$results" "$name"
