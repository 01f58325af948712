#!/usr/bin/env bash
# The maintainer's open-ended fuzzing: each fuzzer explores for MINUTES from a random seed (one
# worker per target, side by side), starting from the seed corpus and, across calls, from what
# earlier calls of this script explored (<build>/corpus-long). Every input that crashes, leaks,
# trips a sanitizer or runs past TIMEOUT seconds is copied into tests/fuzz/corpus/<target>/ as
# found_<sha1>: fix it, check that faults:fuzz_corpus passes, and commit it; from then on every CI
# run (scripts/fuzz.sh, faults:fuzz_corpus) replays it. Not part of CI: its verdict is luck.
# Usage: scripts/fuzz_long.sh [MINUTES [TIMEOUT]]   (default 10 minutes per target, 20 s: an input
#        under the sanitizers runs several times slower than in Release, where bench/corpus_times.sh
#        holds every corpus input to 5 s)
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=${1:-10}
timeout=${2:-20}
for n in "$minutes" "$timeout"; do
  case $n in '' | *[!0-9]*) echo "fuzz_long.sh: MINUTES and TIMEOUT must be whole numbers, got '$n'" >&2; exit 2 ;; esac
done
source scripts/fuzz_setup.sh
seeds=$build/corpus-seeds
explored=$build/corpus-long
found=$build/crashes-long
seed_corpus "$seeds"
mkdir -p "$explored/scene" "$explored/expression"
rm -rf "$found"
mkdir -p "$found"

run_target() {
  local target=$1
  # The first directory receives what the run adds; the second only seeds it.
  "$build/tests/fuzz/nhc_${target}_fuzzer" "$explored/$target" "$seeds/$target" -seed=0 \
    -max_total_time=$((minutes * 60)) -max_len=4096 -timeout="$timeout" -rss_limit_mb=2048 \
    -artifact_prefix="$found/${target}-" -print_final_stats=1 -ignore_crashes=1 -ignore_timeouts=1 \
    -ignore_ooms=1 -fork=1 > "$build/${target}-long.log" 2>&1
}

echo "fuzz_long: $minutes min per target, time limit $timeout s per input; logs in $build/*-long.log"
pids=()
for target in scene expression; do run_target "$target" & pids+=($!); done
for pid in "${pids[@]}"; do wait "$pid" || true; done

kept=0
for f in "$found"/*; do
  [ -e "$f" ] || continue
  name=$(basename "$f")
  target=${name%%-*}
  case $name in *slow-unit-*) continue ;; esac   # slow, not hung: bench/corpus_times.sh's business
  dest=tests/fuzz/corpus/$target/found_$(sha1sum "$f" | cut -c1-16)
  [ "$target" = scene ] && dest=$dest.toml
  [ -e "$dest" ] && continue
  # An input the corpus already holds (a known slow one, say) is no find.
  known=no
  for seed in "$seeds/$target"/*; do cmp -s "$f" "$seed" && { known=yes; break; }; done
  if [ $known = yes ]; then echo "fuzz_long: ${name%%-*} fuzzer: $(echo "$name" | cut -d- -f2) on an input the corpus holds: $f"; continue; fi
  cp "$f" "$dest"
  echo "fuzz_long: ${name%%-*} fuzzer: $(echo "$name" | cut -d- -f2) -> $dest"
  kept=$((kept + 1))
done
for target in scene expression; do
  echo "fuzz_long: nhc_${target}_fuzzer: $(grep -cE '^#[0-9]+.*(NEW|REDUCE)' "$build/${target}-long.log" || true) coverage steps," \
    "explored corpus $(ls "$explored/$target" | wc -l) files"
done
echo "fuzz_long: $kept new input(s) in tests/fuzz/corpus/"
