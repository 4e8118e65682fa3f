#!/usr/bin/env bash
# Runs every libFuzzer target (fuzz/, docs/security.md) for SECONDS each, GSLIFT_FUZZ_JOBS of them
# at a time (default 1: one process, one core, the machine is shared), and records executions,
# speed, corpus growth and findings per parser in RESULTS.json and RESULTS.csv.
#   bench/fuzz/run.sh [SECONDS=600] [RESULTS=bench/results/fuzz] [TARGET[:SECONDS]...]
# A TARGET:SECONDS runs that target for its own time (the slow parsers need longer for 10^6
# executions). Rows of targets not run this time are kept from an existing RESULTS.json, each with
# the date it was measured, so one record can be completed target by target.
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

# ccache where it is installed (a developer machine), plain compiles where not (CI).
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$src" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
        -DGSLIFT_FUZZ=ON -DGSLIFT_BUILD_BENCH=OFF ${launcher[@]+"${launcher[@]}"} >/dev/null || exit 2
fi
cmake --build "$build" -j2 --target fuzz_all >/dev/null || { echo "fuzz build failed" >&2; exit 2; }
"$src/fuzz/make_seeds.sh" "$build" "$build/seeds" || exit 2

mkdir -p "$(dirname "$results")"
scratch_root=$( [ -d /dev/shm ] && [ -w /dev/shm ] && echo /dev/shm || echo "$build/tmp" )/gslift_fuzz_$$
trap 'rm -rf "$scratch_root"' EXIT
rows="$scratch_root/rows.jsonl"
mkdir -p "$scratch_root"
jobs=${GSLIFT_FUZZ_JOBS:-1}
# fuzz_one SPEC: runs one target and appends its row to $rows (one short line per write, so rows of
# targets running side by side do not interleave).
fuzz_one() {
  local spec=$1 t secs bin corpus artifacts scratch before log rc execs speed added rss units findings state
  t=${spec%%:*}
  secs=$seconds
  [[ "$spec" == *:* ]] && secs=${spec#*:}
  bin="$build/fuzz/${t}_fuzz"
  corpus="$build/corpus/$t"
  artifacts="$build/artifacts/$t"
  # The targets write each input to a file (the readers take paths): on tmpfs, or disk I/O is the
  # bottleneck (colmap_text: 200 executions/s on disk, 7500/s on /dev/shm).
  scratch="$scratch_root/$t"
  mkdir -p "$corpus" "$artifacts" "$scratch"
  before=$(find "$artifacts" -type f | wc -l)
  # One log per record and target: a smoke run beside a long one must not write into its log.
  log="$build/logs/$(basename "$results")-$t.log"
  mkdir -p "$(dirname "$log")"
  # -timeout: one input taking 25 s is a hang; -rss_limit_mb: 2 GB is an unbounded allocation;
  # -max_len: 1 MB, the size of make_seeds.cpp's deep-nesting seeds and room to grow them
  # (libFuzzer otherwise starts from 4 KB and grows lengths slowly).
  TMPDIR="$scratch" timeout $((secs + 300)) "$bin" "$corpus" "$build/seeds/$t" \
    -max_total_time="$secs" -timeout=25 -rss_limit_mb=2048 -max_len=1048576 -print_final_stats=1 \
    -artifact_prefix="$artifacts/" >"$log" 2>&1
  rc=$?
  rm -rf "$scratch"
  # -a: libFuzzer's log holds raw input bytes, and grep would answer "binary file matches".
  stat() { grep -a -m1 "^stat::$1:" "$log" | awk '{print $2}'; }
  execs=$(stat number_of_executed_units); speed=$(stat average_exec_per_sec)
  added=$(stat new_units_added); rss=$(stat peak_rss_mb)
  units=$(find "$corpus" -type f | wc -l)
  findings=$(( $(find "$artifacts" -type f | wc -l) - before ))
  state=ok
  if [ $rc -ne 0 ] || [ "$findings" -gt 0 ]; then state="finding (exit $rc, see $log)"; fi
  echo "{\"target\": \"$t\", \"seconds\": $secs, \"executions\": ${execs:-0}, \"execs_per_s\": ${speed:-0}, \"corpus_units\": $units, \"new_units\": ${added:-0}, \"peak_rss_mb\": ${rss:-0}, \"findings\": $findings, \"status\": \"$state\", \"date\": \"$(date -u +%Y-%m-%dT%H:%M:%SZ)\"}" >> "$rows"
  echo "$t: ${execs:-0} executions (${speed:-0}/s), corpus $units, findings $findings, $state"
}
for spec in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n; done
  fuzz_one "$spec" &
done
wait
status=0
[ "$(grep -c '"status": "ok"' "$rows")" -eq "${#targets[@]}" ] || status=1
# The record: this run's rows, then the earlier rows of targets not run now, in the targets' order.
python3 - "$results" "$rows" "$(clang++ --version | head -1 | grep -o '[0-9][0-9.]*' | head -1)" \
  "$(nproc)" "$jobs" <<'PY' || status=2
import json, os, sys
results, rows_file, clang, cores, jobs = sys.argv[1:]
order = ["graph_yaml", "capture_yaml", "colmap_text", "colmap_binary", "transforms_json",
         "vlm_reply", "coco_rle", "mask_png", "depth_image", "ply"]
new = [json.loads(l) for l in open(rows_file)] if os.path.exists(rows_file) else []
old = []
if os.path.exists(results + ".json"):
    prev = json.load(open(results + ".json"))
    old = [dict(r, date=r.get("date", prev.get("date"))) for r in prev.get("targets", [])]
ran = {r["target"] for r in new}
rows = new + [r for r in old if r["target"] not in ran]
rows.sort(key=lambda r: order.index(r["target"]) if r["target"] in order else len(order))
doc = {"tool": "libFuzzer (clang %s) + ASan + UBSan" % clang,
       "machine": "%s cores, shared; %s target(s) at a time, one process each" % (cores, jobs),
       "targets": rows,
       "total_executions": sum(r["executions"] for r in rows),
       "total_findings": sum(r["findings"] for r in rows)}
tmp = results + ".json.tmp"
with open(tmp, "w") as f:
    json.dump(doc, f, indent=1)
    f.write("\n")
os.replace(tmp, results + ".json")
cols = ["target", "seconds", "executions", "execs_per_s", "corpus_units", "new_units",
        "peak_rss_mb", "findings", "status", "date"]
with open(results + ".csv.tmp", "w") as f:
    f.write(",".join(cols) + "\n")
    for r in rows:
        f.write(",".join(str(r.get(c, "")) for c in cols) + "\n")
os.replace(results + ".csv.tmp", results + ".csv")
PY
exit $status
