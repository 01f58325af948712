#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer and UndefinedBehaviorSanitizer (clang, -O1, in
# ./build-asan) and runs it; any sanitizer report fails the test that produced it. The same build
# holds the libFuzzer targets (NHC_FUZZ: the libraries carry the fuzzers' coverage
# instrumentation too), so scripts/fuzz.sh can reuse it: NHC_FUZZ_BUILD_DIR=build-asan.
#
# Which tests: the parsers, the derivation, the structural analysis, the code generator and the
# runtime, each through its unit tests, plus the command line on the malformed-scene corpus and
# `nhc simulate` end to end (the sanitized nhc compiles, loads and integrates a generated model),
# and the Python module's threads (python:threads_asan, tests/CMakeLists.txt), and guesses whose
# rows do not fit their header or whose t is NaN, from the command line and from Python
# (cli:optimize_guess_rows, python:guess_asan: a read past a row's end and a crash, once).
# The code generator's tests run from nhc_tests_codegen_units (tests/codegen/CMakeLists.txt):
# nhc_tests_codegen itself compiles some twenty generated headers into its binary, plain double
# arithmetic that the Release suite checks, and would double this build's time. Left out as
# well: the LaTeX test (pdflatex, not our memory) and the paper check (the derivation tests
# already run the same code here).
# Usage: scripts/sanitize.sh [CTEST_ARGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${NHC_ASAN_BUILD_DIR:-build-asan}
jobs=$(nproc 2>/dev/null || echo 2)

# GiNaC and CLN keep caches alive until exit; everything else must be freed.
# symbolize=0: the suppressions name modules (tests/fuzz/lsan.supp), which LSan matches without
# symbols, but with symbolize=1 every sanitized process starts llvm-symbolizer at its exit to look
# at those caches' allocations: half the processor time of a short nhc run (bench/test-suite-time.md).
# The verdicts are the same either way; reports name module+offset, and the tests that fail run
# once more with symbols (below), so that their reports name functions, files and lines.
lsan_options="suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0"
export LSAN_OPTIONS="$lsan_options:symbolize=0"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

CXX=${CXX_SANITIZE:-clang++} cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" -DNHC_FUZZ=ON -DNHC_SANITIZE=ON -DNHC_BUILD_TESTS=ON >/dev/null
targets=(nhc nhc_tests_scene nhc_tests_derive nhc_tests_analysis nhc_tests_cli nhc_tests_runtime
         nhc_tests_codegen_units nhc_test_appell_hamel_module nhc_scene_fuzzer nhc_expression_fuzzer)
# The Python module, when it is configured (python/CMakeLists.txt skips it without pybind11):
# python:threads_asan runs Python threads doing symbolic work at once through it.
# grep reads the whole list (-q would stop at the first match, and under pipefail the listing's
# SIGPIPE would make the test false).
if cmake --build "$build" --target help | grep -w _nhc >/dev/null; then targets+=(_nhc nhc_python); fi
cmake --build "$build" -j "$jobs" --target "${targets[@]}"

# ctest names: <executable>:<test case> (catch_discover_tests) and cli:simulate_* (add_test).
selected='^(nhc_tests_(scene|derive|analysis|runtime|codegen_units):|nhc_tests_cli:(malformed|bad|a |JSON)|cli:(simulate_(appell_hamel|particle_chetaev_uniform|vakonomic_singular_branch)|concurrent_cache|interrupt_leaves_no_partial_file|optimize_guess_rows)$|python:(threads|guess)_asan$)'
if ! ctest --test-dir "$build" --output-on-failure -j "$jobs" -R "$selected" "$@"; then
  echo "sanitize: the failed tests once more, their reports symbolized:" >&2
  LSAN_OPTIONS="$lsan_options" ctest --test-dir "$build" --output-on-failure --rerun-failed || true
  exit 1
fi
