# Sourced by scripts/fuzz.sh and scripts/fuzz_long.sh: builds the libFuzzer targets with clang
# (AddressSanitizer + UndefinedBehaviorSanitizer, the libraries instrumented for coverage too) and
# writes a fresh seed corpus for both targets.
# Sets: build (NHC_FUZZ_BUILD_DIR, default build-fuzz; scripts/sanitize.sh's build-asan holds the
# same targets with the same instrumentation) and jobs (cores).
build=${NHC_FUZZ_BUILD_DIR:-build-fuzz}
jobs=$(nproc 2>/dev/null || echo 2)
if [ ! -f "$build/CMakeCache.txt" ]; then
  CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
    -DNHC_FUZZ=ON -DNHC_BUILD_TESTS=OFF >/dev/null
fi
export LSAN_OPTIONS="suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0"
cmake --build "$build" -j "$jobs" --target nhc_scene_fuzzer nhc_expression_fuzzer

# seed_corpus DIR: DIR/scene and DIR/expression from scratch: the example scenes, tests/bad/,
# tests/fuzz/corpus/ (every input the fuzzers ever found) and every expression of the examples.
seed_corpus() {
  local work=$1
  rm -rf "$work"
  mkdir -p "$work/scene" "$work/expression"
  cp examples/*.toml tests/bad/*.toml "$work/scene/"
  cp tests/fuzz/corpus/scene/* "$work/scene/" 2>/dev/null || true
  cp tests/fuzz/corpus/expression/* "$work/expression/" 2>/dev/null || true
  grep -hoE '"[^"]*"' examples/*.toml | tr -d '"' | sort -u | awk -v dir="$work/expression" \
    '{ f = sprintf("%s/example_%03d", dir, NR); printf "%s", $0 > f; close(f) }'
}
