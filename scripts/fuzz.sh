#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (AddressSanitizer + UndefinedBehaviorSanitizer) in
# ./build-fuzz and runs each for a bounded time, seeded with the scene corpus.
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 30)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
jobs=$(nproc 2>/dev/null || echo 2)
CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNHC_FUZZ=ON \
  -DNHC_BUILD_TESTS=OFF >/dev/null
cmake --build build-fuzz -j "$jobs" --target nhc_scene_fuzzer nhc_expression_fuzzer

work=build-fuzz/corpus
mkdir -p "$work/scene" "$work/expression" build-fuzz/crashes
cp examples/*.toml tests/bad/*.toml tests/fuzz/corpus/scene/* "$work/scene/" 2>/dev/null || true
cp tests/fuzz/corpus/expression/* "$work/expression/" 2>/dev/null || true

export LSAN_OPTIONS="suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0"
status=0
for target in scene expression; do
  echo "fuzz: nhc_${target}_fuzzer for ${seconds}s"
  if ! build-fuzz/tests/fuzz/nhc_${target}_fuzzer "$work/$target" \
      -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
      -artifact_prefix=build-fuzz/crashes/ -print_final_stats=1 2> "build-fuzz/${target}.log"; then
    echo "fuzz: nhc_${target}_fuzzer found a failure:" >&2
    tail -n 40 "build-fuzz/${target}.log" >&2
    status=1
  fi
  grep -E "stat::number_of_executed_units|stat::new_units_added" "build-fuzz/${target}.log" || true
done
exit $status
