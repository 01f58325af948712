#!/usr/bin/env bash
# The same scene gives the same header in every run. Ten runs of `nhc generate` on each
# example and on the Whipple bicycle (a header of about 230 kB) must write byte-identical headers,
# started from this shell with address-space layout randomization as the system has it (nhc fixes
# its own layout: cli/fixed_address_layout.hpp).
# Usage: same_header_test.sh NHC SOURCE_DIR SCRATCH_DIR [RUNS]
set -euo pipefail
nhc=$1
source_dir=$2
scratch=$3
runs=${4:-10}
rm -rf "$scratch"
mkdir -p "$scratch"
echo "kernel.randomize_va_space = $(cat /proc/sys/kernel/randomize_va_space 2>/dev/null || echo unknown)"

failures=0
for scene in "$source_dir"/examples/*.toml "$source_dir"/examples/whipple/whipple_bicycle.toml; do
  first=""
  for ((k = 1; k <= runs; ++k)); do
    rm -rf "$scratch/run"
    "$nhc" generate "$scene" --quiet -o "$scratch/run" > "$scratch/log" 2>&1 || {
      echo "FAIL: nhc generate $scene exited non-zero:"; cat "$scratch/log"; exit 1; }
    digest=$(cat "$scratch"/run/*.hpp | sha256sum | cut -d' ' -f1)
    if [ -z "$first" ]; then
      first=$digest
      cp -r "$scratch/run" "$scratch/first"
    elif [ "$digest" != "$first" ]; then
      echo "FAIL: $(basename "$scene"): run $k wrote a header different from run 1:"
      diff -r "$scratch/first" "$scratch/run" | head -5 || true
      failures=$((failures + 1))
      break
    fi
  done
  rm -rf "$scratch/first"
  echo "$(basename "$scene"): $runs runs, one header ($(cat "$scratch"/run/*.hpp | wc -c) bytes)"
done
[ "$failures" = 0 ] || { echo "$failures scene(s) gave different headers"; exit 1; }
echo "ok"
