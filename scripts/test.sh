#!/usr/bin/env bash
# Set up and build as run.sh does, then run the whole test suite with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j "$jobs" "$@"
# The suite again under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan), then the
# parser fuzzers for 30 s each on the same build, seeded with the scene corpora.
./scripts/sanitize.sh
NHC_FUZZ_BUILD_DIR=build-asan ./scripts/fuzz.sh 30
