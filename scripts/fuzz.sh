#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (AddressSanitizer + UndefinedBehaviorSanitizer, the
# libraries instrumented for coverage too) and runs each in two deterministic phases, so that one
# commit always gets one verdict:
#   1. replay: every input of the seed corpus (the example scenes, tests/bad/ and
#      tests/fuzz/corpus/, where every input the fuzzers ever found is kept) runs once;
#   2. explore: a fixed number of mutations from a fixed seed (-seed, -runs), one worker, starting
#      from a fresh copy of the seed corpus.
# The targets run side by side when there is more than one core. Every input that crashes, leaks,
# trips a sanitizer or runs past the time limit fails the run; it is kept in <build>/crashes/ and
# belongs, once fixed, in tests/fuzz/corpus/<target>/. Random, open-ended fuzzing is the
# maintainer's scripts/fuzz_long.sh.
# Usage: scripts/fuzz.sh [RUNS_PER_TARGET]   (default 20000 mutations after the replay)
# NHC_FUZZ_BUILD_DIR: build directory (default build-fuzz; scripts/sanitize.sh's build-asan holds
# the same targets with the same instrumentation). NHC_FUZZ_SEED: the seed (default 1).
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-20000}
seed=${NHC_FUZZ_SEED:-1}
case $runs in '' | *[!0-9]*) echo "fuzz.sh: RUNS_PER_TARGET must be a whole number, got '$runs'" >&2; exit 2 ;; esac
build=${NHC_FUZZ_BUILD_DIR:-build-fuzz}
jobs=$(nproc 2>/dev/null || echo 2)
if [ ! -f "$build/CMakeCache.txt" ]; then
  CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
    -DNHC_FUZZ=ON -DNHC_BUILD_TESTS=OFF >/dev/null
fi
export LSAN_OPTIONS="suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0"
cmake --build "$build" -j "$jobs" --target nhc_scene_fuzzer nhc_expression_fuzzer

work=$build/corpus
# A fresh copy every time: inputs an earlier run added would change what this one explores.
rm -rf "$work" "$build/crashes"
mkdir -p "$work/scene" "$work/expression" "$build/crashes"
cp examples/*.toml tests/bad/*.toml "$work/scene/"
cp tests/fuzz/corpus/scene/* "$work/scene/" 2>/dev/null || true
cp tests/fuzz/corpus/expression/* "$work/expression/" 2>/dev/null || true
# Every expression of the example scenes is a seed of the expression fuzzer.
grep -hoE '"[^"]*"' examples/*.toml | tr -d '"' | sort -u | awk -v dir="$work/expression" \
  '{ f = sprintf("%s/example_%03d", dir, NR); printf "%s", $0 > f; close(f) }'

# The time limit (-timeout) only catches hangs: under the sanitizers an input runs several times
# slower than in a Release build, where bench/corpus_times.sh holds every corpus input to 5 s.
run_target() {
  local target=$1
  local fuzzer=$build/tests/fuzz/nhc_${target}_fuzzer
  local common=(-max_len=4096 -timeout=60 -rss_limit_mb=2048 -artifact_prefix="$build/crashes/${target}-")
  "$fuzzer" "$work/$target" -runs=0 "${common[@]}" > "$build/${target}-replay.log" 2>&1 &&
    "$fuzzer" "$work/$target" -seed="$seed" -runs="$runs" "${common[@]}" -print_final_stats=1 \
      > "$build/${target}.log" 2>&1
}

status=0
pids=()
for target in scene expression; do
  echo "fuzz: nhc_${target}_fuzzer: replay of the corpus, then $runs runs from seed $seed"
  if [ "$jobs" -gt 1 ]; then
    run_target "$target" & pids+=($!)
  else
    run_target "$target" || status=1
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
for target in scene expression; do
  for log in "$build/${target}-replay.log" "$build/${target}.log"; do
    [ -f "$log" ] || continue
    if grep -qE "^==[0-9]+==ERROR|runtime error:|ALARM: working on the last Unit|SUMMARY: libFuzzer" "$log"; then
      echo "fuzz: nhc_${target}_fuzzer found a failure ($log):" >&2
      tail -n 60 "$log" >&2
      status=1
    fi
  done
  log=$build/${target}.log
  [ -f "$log" ] || { echo "fuzz: nhc_${target}_fuzzer did not get past the replay" >&2; status=1; continue; }
  echo "fuzz: nhc_${target}_fuzzer: $(grep -E '^stat::number_of_executed_units' "$log" | awk '{print $2}') inputs," \
    "$(grep -E '^stat::new_units_added' "$log" | awk '{print $2}') new, corpus $(ls "$work/$target" | wc -l) files"
done
# libFuzzer also saves inputs slower than 10 s (slow-unit-*); they are reported, not failures
# (a slow input's time depends on the machine; bench/corpus_times.sh measures the corpus).
for f in "$build"/crashes/*; do
  [ -e "$f" ] || continue
  case $(basename "$f") in
    *slow-unit-*) echo "fuzz: slow input (over 10 s, under the 60 s limit): $f" >&2 ;;
    *) echo "fuzz: failing input: $f" >&2 ;;
  esac
done
exit $status
