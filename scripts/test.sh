#!/usr/bin/env bash
# Set up and build as run.sh does, then run the test suite with ctest and the quick benchmark. Tests labelled `slow`
# (minutes each: the Whipple bicycle's sweep over its speed and its simulation) are left out here to keep CI short;
# NHC_SLOW_TESTS=1 includes them, or run them alone with `ctest --test-dir build -L slow`.
# Each stage prints its wall time to stderr ("test.sh: stage ctest took 580 s"), so that a CI log
# shows where the time goes (bench/test-suite-time.md).
set -euo pipefail
cd "$(dirname "$0")/.."
suite_start=$SECONDS
# stage NAME COMMAND...: runs COMMAND and reports its wall time, whether it passed or failed.
stage() {
  local name=$1 start=$SECONDS rc=0
  shift
  "$@" || rc=$?
  if [ "$rc" = 0 ]; then
    echo "test.sh: stage $name took $((SECONDS - start)) s" >&2
  else
    echo "test.sh: stage $name failed (exit $rc) after $((SECONDS - start)) s" >&2
    exit "$rc"
  fi
}
stage setup ./scripts/setup.sh
# Every C++ file follows .clang-format (docs/architecture.md, "Code format").
stage check_format ./scripts/check_format.sh
jobs=$(nproc 2>/dev/null || echo 2)
# The documentation site (Sphinx, under a minute with the compile cache warm): built before the
# suite, whose docs:links and docs:browser check it.
stage docs cmake --build build --target docs
slow=(-LE slow)
if [ "${NHC_SLOW_TESTS:-0}" = 1 ]; then slow=(); fi
stage ctest ctest --test-dir build --output-on-failure -j "$jobs" "${slow[@]}" "$@"
# The benchmark harness on small N (bench/run.sh --quick, under a minute; its report goes to
# build/bench-out/results.md, bench/results.md is left alone): it must keep running end to end.
stage bench env NHC_BENCH_BUILD_DIR=build ./bench/run.sh --quick
# The suite again under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan), then the
# parser fuzzers on the same build: the whole corpus, then a fixed number of mutations from a fixed
# seed, so that one commit gets one verdict (random, open-ended fuzzing is scripts/fuzz_long.sh).
stage sanitize ./scripts/sanitize.sh
stage fuzz env NHC_FUZZ_BUILD_DIR=build-asan ./scripts/fuzz.sh
echo "test.sh: the whole suite took $((SECONDS - suite_start)) s" >&2
