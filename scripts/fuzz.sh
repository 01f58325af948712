#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (AddressSanitizer + UndefinedBehaviorSanitizer, the
# libraries instrumented for coverage too) and runs each for a bounded time, seeded with the
# example scenes, the malformed-scene corpus tests/bad/ and tests/fuzz/corpus/. The targets run
# side by side when there is more than one core. Every input that crashes, leaks, trips a
# sanitizer or times out fails the run; it is kept in <build>/crashes/ and belongs, once fixed,
# in tests/fuzz/corpus/<target>/.
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 30)
# NHC_FUZZ_BUILD_DIR: build directory (default build-fuzz; scripts/sanitize.sh's build-asan holds
# the same targets with the same instrumentation).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
build=${NHC_FUZZ_BUILD_DIR:-build-fuzz}
jobs=$(nproc 2>/dev/null || echo 2)
if [ ! -f "$build/CMakeCache.txt" ]; then
  CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
    -DNHC_FUZZ=ON -DNHC_BUILD_TESTS=OFF >/dev/null
fi
export LSAN_OPTIONS="suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0"
cmake --build "$build" -j "$jobs" --target nhc_scene_fuzzer nhc_expression_fuzzer

work=$build/corpus
mkdir -p "$work/scene" "$work/expression" "$build/crashes"
cp examples/*.toml tests/bad/*.toml "$work/scene/"
cp tests/fuzz/corpus/scene/* "$work/scene/" 2>/dev/null || true
cp tests/fuzz/corpus/expression/* "$work/expression/" 2>/dev/null || true
# Every expression of the example scenes is a seed of the expression fuzzer.
grep -hoE '"[^"]*"' examples/*.toml | tr -d '"' | sort -u | awk -v dir="$work/expression" \
  '{ f = sprintf("%s/example_%03d", dir, NR); printf "%s", $0 > f; close(f) }'

run_target() {
  local target=$1
  "$build/tests/fuzz/nhc_${target}_fuzzer" "$work/$target" \
    -max_total_time="$seconds" -max_len=4096 -timeout=30 -rss_limit_mb=2048 \
    -artifact_prefix="$build/crashes/${target}-" -print_final_stats=1 > "$build/${target}.log" 2>&1
}

status=0
pids=()
for target in scene expression; do
  echo "fuzz: nhc_${target}_fuzzer for ${seconds}s"
  if [ "$jobs" -gt 1 ]; then
    run_target "$target" & pids+=($!)
  else
    run_target "$target" || status=1
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
for target in scene expression; do
  log=$build/${target}.log
  if grep -qE "^==[0-9]+==ERROR|runtime error:|ALARM: working on the last Unit|SUMMARY: libFuzzer" "$log"; then
    echo "fuzz: nhc_${target}_fuzzer found a failure:" >&2
    tail -n 60 "$log" >&2
    status=1
  fi
  echo "fuzz: nhc_${target}_fuzzer: $(grep -E '^stat::number_of_executed_units' "$log" | awk '{print $2}') inputs," \
    "$(grep -E '^stat::new_units_added' "$log" | awk '{print $2}') new, corpus $(ls "$work/$target" | wc -l) files"
done
# libFuzzer also saves inputs slower than 10 s (slow-unit-*); they are reported, not failures.
for f in "$build"/crashes/*; do
  [ -e "$f" ] || continue
  case $(basename "$f") in
    *slow-unit-*) echo "fuzz: slow input (over 10 s, under the 30 s limit): $f" >&2 ;;
    *) echo "fuzz: failing input: $f" >&2 ;;
  esac
done
exit $status
