#!/usr/bin/env bash
# CI-sized fuzzing (docs/security.md): every libFuzzer target for SECONDS (default 30) on the
# grown corpus, failing on any crash, sanitizer report, leak, hang or out-of-memory. Needs clang
# and libFuzzer (Debian: clang, libfuzzer-14-dev); builds build-fuzz on first use.
#   tests/fuzz_smoke.sh [SECONDS=30]
set -uo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
build=${GSLIFT_FUZZ_BUILD:-$src/build-fuzz}
exec "$src/bench/fuzz/run.sh" "${1:-30}" "$build/fuzz_smoke"
