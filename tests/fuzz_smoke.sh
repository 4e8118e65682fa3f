#!/usr/bin/env bash
# CI-sized fuzzing (docs/security.md): every libFuzzer target for SECONDS (default 10) on the
# grown corpus, two at a time (GSLIFT_FUZZ_JOBS: one per core of CI's two), failing on any crash,
# sanitizer report, leak, hang or out-of-memory. Needs clang
# and libFuzzer (Debian: clang, libclang-rt-14-dev). Uses the sanitizer suite's build
# (GSLIFT_FUZZ_BUILD, default build-san: tests/sanitize_suite.sh), configuring it first if absent.
#   tests/fuzz_smoke.sh [SECONDS=10]
set -uo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
build=${GSLIFT_FUZZ_BUILD:-$src/build-san}
GSLIFT_FUZZ_JOBS=${GSLIFT_FUZZ_JOBS:-2} GSLIFT_FUZZ_BUILD=$build exec "$src/bench/fuzz/run.sh" "${1:-10}" "$build/fuzz_smoke"
