#!/usr/bin/env bash
# Builds the libFuzzer targets (scripts/fuzz_setup.sh) and runs each deterministically, so that one
# commit always gets one verdict: each starts from a fresh copy of the seed corpus (the example
# scenes, tests/bad/ and tests/fuzz/corpus/, where every input the fuzzers ever found is kept),
# runs every input of it once (libFuzzer's INITED line: the replay), then explores a fixed number
# of mutations from a fixed seed (-seed, -runs) with one worker.
# The targets run side by side when there is more than one core. Every input that crashes, leaks,
# trips a sanitizer or runs past the time limit fails the run; it is kept in <build>/crashes/ and
# belongs, once fixed, in tests/fuzz/corpus/<target>/. Random, open-ended fuzzing is the
# maintainer's scripts/fuzz_long.sh.
# Before the fuzzers, every corpus input goes through the symbolic stages (derive and generate) in
# the Release build with a limit of processor time per input (tests/fuzz/replay_derive.sh).
# Usage: scripts/fuzz.sh [SCENE_RUNS [EXPRESSION_RUNS]]   (inputs in all, the replay included;
#        default 3000 and 100000: about a minute each under the sanitizers on one core)
# NHC_FUZZ_BUILD_DIR: build directory (default build-fuzz; scripts/sanitize.sh's build-asan holds
# the same targets with the same instrumentation). NHC_FUZZ_SEED: the seed (default 1).
set -euo pipefail
cd "$(dirname "$0")/.."
scene_runs=${1:-3000}
expression_runs=${2:-100000}
seed=${NHC_FUZZ_SEED:-1}
for runs in "$scene_runs" "$expression_runs" "$seed"; do
  case $runs in '' | *[!0-9]*) echo "fuzz.sh: runs and seed must be whole numbers, got '$runs'" >&2; exit 2 ;; esac
done
source scripts/fuzz_setup.sh
work=$build/corpus
# A fresh copy every time: inputs an earlier run added would change what this one explores.
seed_corpus "$work"
rm -rf "$build/crashes"
mkdir -p "$build/crashes"

# The time limit (-timeout): under the sanitizers an input runs several times slower than in a
# Release build, where bench/corpus_times.sh holds every corpus input to 5 s.
runs_of() { if [ "$1" = scene ]; then echo "$scene_runs"; else echo "$expression_runs"; fi; }
# Address-space randomization off where the system allows it: GiNaC orders terms partly by
# address, so with it the same seed can take other paths through the code and add other inputs.
no_aslr=()
if setarch "$(uname -m)" -R true 2>/dev/null; then no_aslr=(setarch "$(uname -m)" -R); fi
run_target() {
  local target=$1
  "${no_aslr[@]}" "$build/tests/fuzz/nhc_${target}_fuzzer" "$work/$target" -seed="$seed" -runs="$(runs_of "$target")" \
    -max_len=4096 -timeout="$replay_timeout" -rss_limit_mb=2048 -artifact_prefix="$build/crashes/${target}-" \
    -print_final_stats=1 > "$build/${target}.log" 2>&1
}

# First every seed input by itself, named: a corpus input slower than the time limit (or larger
# than the memory limit) fails the run with its file named, the same on every machine that is not
# five times slower than this one. 20 s under the sanitizers is about 5 s in a Release build, where
# the command line's work limit (4 s of symbolic work) stops a runaway scene.
replay_timeout=${NHC_FUZZ_TIMEOUT:-20}
status=0

# Then every corpus input through the symbolic stages (derive, print, reduce, generate, under the work budget),
# in the Release build (under the sanitizers the work is 5-10 times slower, and so is its budget):
# at most NHC_REPLAY_SECONDS (10) of processor time and 2 GB each, or the run fails naming the input
# (tests/fuzz/replay_derive.sh). The parsers' fuzzers below never derive.
replay_build=${NHC_REPLAY_BUILD_DIR:-build}
if [ ! -f "$replay_build/CMakeCache.txt" ]; then
  echo "fuzz: no Release build in $replay_build for the derive replay (scripts/setup.sh; NHC_REPLAY_BUILD_DIR)" >&2
  exit 1
fi
cmake --build "$replay_build" --target nhc_derive_replay -j "$jobs" > "$build/replay-build.log" 2>&1 ||
  { tail -n 30 "$build/replay-build.log" >&2; exit 1; }
echo "fuzz: every corpus input through derive and generate, at most ${NHC_REPLAY_SECONDS:-10} s of processor time each"
phase_start=$SECONDS
tests/fuzz/replay_derive.sh "$replay_build/tests/faults/nhc_derive_replay" "$build/replay" "${NHC_REPLAY_SECONDS:-10}" ||
  status=1
echo "fuzz.sh: the derive replay took $((SECONDS - phase_start)) s" >&2
phase_start=$SECONDS
for target in scene expression; do
  log=$build/${target}-replay.log
  echo "fuzz: nhc_${target}_fuzzer: every corpus input once, at most ${replay_timeout} s each"
  if ! "${no_aslr[@]}" "$build/tests/fuzz/nhc_${target}_fuzzer" -timeout="$replay_timeout" -rss_limit_mb=2048 \
      -artifact_prefix="$build/crashes/${target}-" "$work/$target"/* > "$log" 2>&1; then
    echo "fuzz: nhc_${target}_fuzzer failed on $(grep -E '^Running: ' "$log" | tail -n 1 | cut -d' ' -f2-):" >&2
    tail -n 30 "$log" >&2
    status=1
  fi
done
echo "fuzz.sh: the fuzzers' corpus replay took $((SECONDS - phase_start)) s" >&2
[ $status = 0 ] || exit $status

phase_start=$SECONDS
pids=()
for target in scene expression; do
  echo "fuzz: nhc_${target}_fuzzer: the corpus, then mutations from seed $seed, $(runs_of "$target") inputs in all"
  if [ "$jobs" -gt 1 ]; then
    run_target "$target" & pids+=($!)
  else
    run_target "$target" || status=1
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
echo "fuzz.sh: the mutations took $((SECONDS - phase_start)) s" >&2
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
# libFuzzer also saves inputs slower than 10 s (slow-unit-*); under the time limit they are
# reported, not failures (bench/corpus_times.sh measures the corpus in a Release build).
for f in "$build"/crashes/*; do
  [ -e "$f" ] || continue
  case $(basename "$f") in
    *slow-unit-*) echo "fuzz: slow input (over 10 s, under the ${replay_timeout} s limit): $f" >&2 ;;
    *) echo "fuzz: failing input: $f" >&2 ;;
  esac
done
exit $status
