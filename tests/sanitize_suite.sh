#!/usr/bin/env bash
# sanitize_suite.sh [BUILD_DIR=build-san] [JOBS=2]: builds the project a second time with clang,
# AddressSanitizer, UndefinedBehaviorSanitizer (halting on the first report) and libFuzzer's
# coverage instrumentation (-DGSLIFT_FUZZ=ON: the same build gives tests/fuzz_smoke.sh its
# fuzzers), and runs the library's and the CLI's tests under it: every ctest entry but those
# labelled e2e, the whole-graph accuracy runs, the browser and the process-level kill and Slurm
# tests, which the Release suite runs (docs/security.md). Exits non-zero on a failing test or any
# sanitizer report; prints the build and test times. Leak checking is on; the few leaks of the
# system libraries that are not gslift's to fix are listed in tests/sanitize_suppressions.txt.
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src/build-san}
jobs=${2:-2}
# ccache where it is installed (a developer machine), plain compiles where not (CI).
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
start=$(date +%s)
# -O1: the sanitizers' usual level, for the libraries (the tests' own files: -O0,
# tests/CMakeLists.txt); -pipe keeps the temporary assembly off /tmp; shared libraries: each test
# executable links in seconds instead of copying the instrumented libraries; a unity build with
# precompiled headers as in .ci/build; no e2e executables or [long] cases, which this suite does
# not run.
cmake -S "$src" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_COMPILER=clang++ \
      -DCMAKE_CXX_FLAGS="-O1 -pipe" -DGSLIFT_FUZZ=ON -DGSLIFT_BUILD_BENCH=OFF -DBUILD_SHARED_LIBS=ON \
      -DCMAKE_UNITY_BUILD=ON -DGSLIFT_PRECOMPILE_HEADERS=ON -DGSLIFT_BUILD_E2E_TESTS=OFF \
      -DGSLIFT_TEST_TIMEOUT_SCALE=4 ${launcher[@]+"${launcher[@]}"} >/dev/null
cmake --build "$build" -j "$jobs"
built=$(date +%s)
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=0"
export LSAN_OPTIONS="suppressions=$src/tests/sanitize_suppressions.txt:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
status=0
ctest --test-dir "$build" -j "$jobs" --output-on-failure -LE e2e || status=$?
echo "sanitize suite: build $(( built - start )) s, tests $(( $(date +%s) - built )) s, status $status"
exit $status
