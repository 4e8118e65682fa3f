#!/usr/bin/env bash
# Runs every libFuzzer target (fuzz/, docs/security.md) for SECONDS each, one after the other
# (one process, one core: the machine is shared), and records executions, speed, corpus growth
# and findings per parser in RESULTS.json and RESULTS.csv.
#   bench/fuzz/run.sh [SECONDS=600] [RESULTS=bench/results/fuzz] [TARGET...]
# Configures and builds build-fuzz (clang++, -DGSLIFT_FUZZ=ON) when needed, builds the seeds
# (fuzz/make_seeds.sh), and keeps each target's grown corpus in build-fuzz/corpus/<target> so that
# later runs start where earlier ones stopped. A finding (crash, sanitizer report, leak, timeout,
# out-of-memory) leaves its input in build-fuzz/artifacts/<target>/ and makes the exit status 1;
# each becomes a regression test in tests/data/fuzz_regressions/<target>/.
set -uo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
seconds=${1:-600}
results=${2:-$src/bench/results/fuzz}
shift $(( $# > 2 ? 2 : $# ))
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(graph_yaml capture_yaml colmap_text colmap_binary transforms_json
                                     vlm_reply coco_rle mask_png depth_image ply)
build=${GSLIFT_FUZZ_BUILD:-$src/build-fuzz}

if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$src" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
        -DGSLIFT_FUZZ=ON -DGSLIFT_BUILD_BENCH=OFF -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null || exit 2
fi
cmake --build "$build" -j2 --target fuzz_all >/dev/null || { echo "fuzz build failed" >&2; exit 2; }
"$src/fuzz/make_seeds.sh" "$build" "$build/seeds" || exit 2

mkdir -p "$(dirname "$results")"
scratch_root=$( [ -d /dev/shm ] && [ -w /dev/shm ] && echo /dev/shm || echo "$build/tmp" )/gslift_fuzz_$$
trap 'rm -rf "$scratch_root"' EXIT
csv="$results.csv"
echo "target,seconds,executions,execs_per_s,corpus_units,new_units,peak_rss_mb,findings,status" > "$csv"
json_rows=()
status=0
for t in "${targets[@]}"; do
  bin="$build/fuzz/${t}_fuzz"
  corpus="$build/corpus/$t"
  artifacts="$build/artifacts/$t"
  # The targets write each input to a file (the readers take paths): on tmpfs, or disk I/O is the
  # bottleneck (colmap_text: 200 executions/s on disk, 7500/s on /dev/shm).
  scratch="$scratch_root/$t"
  mkdir -p "$corpus" "$artifacts" "$scratch"
  before=$(find "$artifacts" -type f | wc -l)
  log="$build/logs/$t.log"
  mkdir -p "$(dirname "$log")"
  # -timeout: one input taking 25 s is a hang; -rss_limit_mb: 2 GB is an unbounded allocation.
  TMPDIR="$scratch" timeout $((seconds + 300)) "$bin" "$corpus" "$build/seeds/$t" \
    -max_total_time="$seconds" -timeout=25 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$artifacts/" >"$log" 2>&1
  rc=$?
  rm -rf "$scratch"
  stat() { grep -m1 "^stat::$1:" "$log" | awk '{print $2}'; }
  execs=$(stat number_of_executed_units); speed=$(stat average_exec_per_sec)
  added=$(stat new_units_added); rss=$(stat peak_rss_mb)
  units=$(find "$corpus" -type f | wc -l)
  findings=$(( $(find "$artifacts" -type f | wc -l) - before ))
  state=ok
  if [ $rc -ne 0 ] || [ "$findings" -gt 0 ]; then state="finding (exit $rc, see $log)"; status=1; fi
  echo "$t,$seconds,${execs:-0},${speed:-0},$units,${added:-0},${rss:-0},$findings,$state" >> "$csv"
  json_rows+=("{\"target\": \"$t\", \"seconds\": $seconds, \"executions\": ${execs:-0}, \"execs_per_s\": ${speed:-0}, \"corpus_units\": $units, \"new_units\": ${added:-0}, \"peak_rss_mb\": ${rss:-0}, \"findings\": $findings, \"status\": \"$state\"}")
  echo "$t: ${execs:-0} executions (${speed:-0}/s), corpus $units, findings $findings, $state"
done
{
  echo "{\"tool\": \"libFuzzer (clang $(clang++ --version | head -1 | grep -o '[0-9][0-9.]*' | head -1)) + ASan + UBSan\","
  echo " \"machine\": \"$(nproc) cores, shared; one target at a time, one process\","
  echo " \"date\": \"$(date -u +%Y-%m-%dT%H:%M:%SZ)\","
  echo " \"targets\": ["
  for i in "${!json_rows[@]}"; do
    sep=","; [ "$i" -eq $(( ${#json_rows[@]} - 1 )) ] && sep=""
    echo "  ${json_rows[$i]}$sep"
  done
  echo " ]}"
} > "$results.json"
exit $status
