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
targets=(nhc nhc_tests_scene nhc_tests_derive nhc_tests_analysis nhc_tests_runtime
         nhc_tests_codegen_units nhc_test_appell_hamel_module nhc_scene_fuzzer nhc_expression_fuzzer)
# nhc_tests_cli's selected cases run the nhc binary on the malformed-scene corpus and bad flags:
# what must be sanitized is that binary. With a Release build beside this one (scripts/test.sh
# builds it first; NHC_RELEASE_BUILD_DIR), its test binary runs against the sanitized nhc
# (NHC_TEST_EXECUTABLE, tests/support/command_runner.cpp) instead of compiling its fourteen
# sources under the sanitizers too; without one, it is built here.
release=${NHC_RELEASE_BUILD_DIR:-build}
cli_tests_from_release=0
if [ -x "$release/tests/cli/nhc_tests_cli" ] && [ "$(realpath "$release")" != "$(realpath -m "$build")" ]; then
  cli_tests_from_release=1
else
  targets+=(nhc_tests_cli)
fi
# The Python module, when it is configured (python/CMakeLists.txt skips it without pybind11):
# python:threads_asan runs Python threads doing symbolic work at once through it.
# grep reads the whole list (-q would stop at the first match, and under pipefail the listing's
# SIGPIPE would make the test false).
if cmake --build "$build" --target help | grep -w _nhc >/dev/null; then targets+=(_nhc nhc_python); fi
build_start=$SECONDS
cmake --build "$build" -j "$jobs" --target "${targets[@]}"
echo "sanitize.sh: the build took $((SECONDS - build_start)) s" >&2

# ctest names: <executable>:<test case> (catch_discover_tests) and cli:simulate_* (add_test).
cli_selected='nhc_tests_cli:(malformed|bad|a |JSON)'
selected='^(nhc_tests_(scene|derive|analysis|runtime|codegen_units):|cli:(simulate_(appell_hamel|particle_chetaev_uniform|vakonomic_singular_branch)|concurrent_cache|interrupt_leaves_no_partial_file|optimize_guess_rows)$|python:(threads|guess)_asan$)'
status=0
# run_selected DIR REGEX [ENV...]: the selected tests of one build; a failure runs them once more
# with their reports symbolized (LSAN_OPTIONS without symbolize=0).
run_selected() {
  local dir=$1 regex=$2; shift 2
  if ! env "$@" ctest --test-dir "$dir" --output-on-failure -j "$jobs" -R "$regex" "${ctest_args[@]}"; then
    echo "sanitize: the failed tests once more, their reports symbolized:" >&2
    env "$@" LSAN_OPTIONS="$lsan_options" ctest --test-dir "$dir" --output-on-failure --rerun-failed || true
    status=1
  fi
}
ctest_args=("$@")
tests_start=$SECONDS
if [ "$cli_tests_from_release" = 1 ]; then
  run_selected "$build" "$selected"
  run_selected "$release" "^$cli_selected" NHC_TEST_EXECUTABLE="$PWD/$build/cli/nhc"
else
  run_selected "$build" "^(${selected#^}|$cli_selected)"
fi
echo "sanitize.sh: the tests took $((SECONDS - tests_start)) s" >&2
exit "$status"
