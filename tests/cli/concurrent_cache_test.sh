#!/usr/bin/env bash
# Several `nhc simulate` at once on one empty cache directory: every run succeeds with the same
# CSV and no warning, the cache ends with exactly one shared object for the model, its digest
# matching, and no temporary file, and the next run finds it (cached).
# Usage: concurrent_cache_test.sh NHC SCENE WORK_DIR [RUNS]
set -uo pipefail
nhc=$1 scene=$2 work=$3 runs=${4:-4}
rm -rf "$work" && mkdir -p "$work"
export NHC_CACHE_DIR=$work/cache
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

pids=()
for k in $(seq 1 "$runs"); do
  "$nhc" simulate "$scene" -o "$work/out_$k.csv" >"$work/stdout_$k" 2>"$work/stderr_$k" &
  pids+=($!)
done
for k in $(seq 1 "$runs"); do
  wait "${pids[$((k - 1))]}" || { fail "run $k: exit code $?"; cat "$work/stderr_$k" >&2; }
done
for k in $(seq 2 "$runs"); do
  cmp -s "$work/out_1.csv" "$work/out_$k.csv" || fail "run $k wrote a different CSV"
done
for k in $(seq 1 "$runs"); do
  ! grep -q "warning" "$work/stderr_$k" || fail "run $k warned: $(cat "$work/stderr_$k")"
done
(cd "$NHC_CACHE_DIR" && sha256sum -c --quiet ./*.sha256) || fail "the entry does not match its digest"
[ "$(wc -l < "$work/out_1.csv")" -eq 202 ] || fail "the CSV does not have 201 rows"
libraries=$(find "$NHC_CACHE_DIR" -name '*.so' | wc -l)
[ "$libraries" -eq 1 ] || fail "$libraries shared objects in the cache, expected 1"
leftovers=$(find "$NHC_CACHE_DIR" "$work" -name '*.tmp*')
[ -z "$leftovers" ] || fail "temporary files left: $leftovers"
"$nhc" simulate "$scene" > "$work/stdout_cached" 2>&1 || fail "the run after them failed"
grep -q "(cached)" "$work/stdout_cached" || fail "the run after them did not use the cache"
[ "$failures" -eq 0 ] && echo "concurrent cache test: $runs runs, one cache entry, no temporary file"
exit $((failures > 0))
