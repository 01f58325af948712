#!/usr/bin/env bash
# A run's result does not depend on what the caches hold: nhc simulate on the Whipple bicycle with
# the interpreted backend (which derives the model every run) writes byte-identical CSVs on a cold
# cache, with the initial-point check found in the scene cache, and with the scene cache off.
# (With the check cached the analysis used to be skipped, so the derivation made its symbols in
# another order and GiNaC ordered the terms differently: app/nhc/app/preparation.hpp.)
# Usage: same_result_whatever_cache_test.sh NHC SCENE SCRATCH_DIR
set -euo pipefail
nhc=$1
scene=$2
scratch=$3
rm -rf "$scratch"
mkdir -p "$scratch/cache"
export NHC_CACHE_DIR="$scratch/cache"
unset NHC_SCENE_CACHE

run() {  # run NAME: one simulate into $scratch/NAME.csv
  "$nhc" simulate "$scene" --backend interpreted -o "$scratch/$1.csv" > "$scratch/$1.log" 2>&1 || {
    echo "FAIL: nhc simulate ($1) exited non-zero:"; cat "$scratch/$1.log"; exit 1; }
}

run cold
ls "$scratch"/cache/scenes/*.entry > /dev/null 2>&1 || { echo "FAIL: the cold run stored no initial-point check"; exit 1; }
run check_cached
NHC_SCENE_CACHE=off run cache_off

failures=0
for name in check_cached cache_off; do
  if ! cmp "$scratch/cold.csv" "$scratch/$name.csv"; then
    echo "FAIL: the run with $name wrote another CSV than the cold run"
    failures=$((failures + 1))
  fi
done
[ "$failures" = 0 ] || exit 1
echo "ok: $(wc -l < "$scratch/cold.csv") rows, the same in the three runs"
