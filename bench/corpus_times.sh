#!/usr/bin/env bash
# Hostile inputs against the clock: `nhc derive` on every input of the corpus
# (scripts/corpus_inputs.sh: tests/fuzz/corpus/, tests/bad/, the examples) in a Release build,
# one after the other, wall time each. Prints the ten slowest with their exit codes and writes
# the same table to bench/corpus-times.md (or OUT). Fails when an input ends with an exit code
# other than 0, 2 or 3 or takes longer than the limit (5 s unless NHC_CORPUS_LIMIT says
# otherwise). A benchmark, not a test: its verdict depends on the machine.
# Usage: bench/corpus_times.sh [OUT]   (NHC_BENCH_BUILD_DIR: the Release build, default build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${NHC_BENCH_BUILD_DIR:-build}
out=${1:-bench/corpus-times.md}
limit=${NHC_CORPUS_LIMIT:-5}
nhc=$build/cli/nhc
[ -x "$nhc" ] || { echo "corpus_times: no $nhc (build first: cmake --build $build)" >&2; exit 4; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export NHC_CACHE_DIR=$work/cache
: >"$work/times"
while IFS= read -r scene; do
  start=$(date +%s.%N)
  rc=0
  timeout 300 "$nhc" derive "$scene" >/dev/null 2>&1 || rc=$?
  end=$(date +%s.%N)
  printf '%.3f %d %s\n' "$(echo "$end - $start" | bc)" "$rc" "$scene" >>"$work/times"
done < <(scripts/corpus_inputs.sh "$work/scenes")
sort -rn "$work/times" >"$work/sorted"
total=$(wc -l <"$work/times")
bad=$(awk -v limit="$limit" '$1 > limit || ($2 != 0 && $2 != 2 && $2 != 3)' "$work/sorted" | wc -l)
{
  echo "# Hostile inputs: the ten slowest of $total"
  echo
  echo "\`bench/corpus_times.sh\` on $(date -u +%Y-%m-%d), $(nproc) cores, $(git rev-parse --short HEAD 2>/dev/null || echo '?');"
  echo "\`nhc derive\` on each input of the corpus (Release build), wall time; limit $limit s, exit 0, 2 or 3."
  echo
  echo "| seconds | exit | input |"
  echo "|---:|---:|---|"
  head -n 10 "$work/sorted" | while read -r seconds rc scene; do
    name=${scene#"$PWD"/}
    case $name in /*) name="(expression input) $(basename "$name" .toml | sed 's/^expression_//')" ;; esac
    echo "| $seconds | $rc | $name |"
  done
  echo
  echo "Inputs over the limit or with another exit code: $bad."
} >"$out"
cat "$out"
[ "$bad" -eq 0 ]
