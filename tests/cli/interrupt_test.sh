#!/usr/bin/env bash
# An interrupted `nhc simulate` (and `nhc compare`, section 4) leaves no partial output and no temporary file: SIGINT (and
# SIGTERM) while the model is being compiled into an empty cache, while the CSV is being written,
# and at a spread of moments across a whole run. After each interrupt nhc exits 128 + the signal
# (130 for SIGINT), the output CSV is absent or complete, no *.tmp* file remains beside it or in
# the cache, no compiler is left running, and whatever the cache holds loads and runs.
# Usage: interrupt_test.sh NHC SCENE WORK_DIR
set -uo pipefail
# Job control: background jobs of a script otherwise start with SIGINT ignored, and nhc (like
# any program) keeps a signal ignored that it inherits ignored.
set -m
nhc=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# Fails unless nothing temporary or partial is left in $out_dir and $cache.
check_clean() {
  local what=$1 out_dir=$2 cache=$3 rows=$4
  local leftovers
  leftovers=$(find "$out_dir" "$cache" -name '*.tmp*' 2>/dev/null)
  [ -z "$leftovers" ] || fail "$what: temporary files left: $leftovers"
  local f content
  for f in /proc/[0-9]*/cmdline; do
    content=$(tr '\0' ' ' 2>/dev/null < "$f") || continue
    case $content in
      tr\ *) ;;  # the tr reading its own command line
      *"$cache"*) fail "$what: a process still works in $cache: $content" ;;
    esac
  done
  if [ -f "$out_dir/out.csv" ]; then
    local n
    n=$(wc -l < "$out_dir/out.csv")
    [ "$n" -eq $((rows + 2)) ] || fail "$what: partial CSV with $n lines"
  fi
}

# Starts nhc simulate in the background; sets $pid.
start() {
  local out_dir=$1 cache=$2; shift 2
  NHC_CACHE_DIR=$cache "$nhc" simulate "$scene" -o "$out_dir/out.csv" "$@" \
    >"$out_dir/stdout" 2>"$out_dir/stderr" &
  pid=$!
}

# Waits (up to 120 s) until a file matching $2 exists under $1; returns 1 if the process ended.
wait_for_file() {
  local dir=$1 pattern=$2
  for _ in $(seq 1 12000); do
    [ -n "$(find "$dir" -name "$pattern" 2>/dev/null | head -n 1)" ] && return 0
    kill -0 "$pid" 2>/dev/null || return 1
    sleep 0.01
  done
  return 1
}

interrupted_exit() {
  local signal=$1 expected=$2 what=$3
  wait "$pid"; local rc=$?
  [ "$rc" -eq "$expected" ] || fail "$what: exit code $rc after SIG$signal, expected $expected"
}

# 1. Interrupted while the compiler runs (its temporary source exists in the empty cache).
for signal in INT TERM; do
  d=$work/compile_$signal; mkdir -p "$d/out"
  start "$d/out" "$d/cache"
  if wait_for_file "$d/cache" '*.tmp*'; then
    kill -s "$signal" "$pid"
    expected=130; [ "$signal" = TERM ] && expected=143
    interrupted_exit "$signal" "$expected" "compile/$signal"
    check_clean "compile/$signal" "$d/out" "$d/cache" 200
    [ -z "$(find "$d/cache" -name '*.so' 2>/dev/null)" ] || fail "compile/$signal: a cache entry appeared"
    [ ! -e "$d/out/out.csv" ] || fail "compile/$signal: the CSV was written"
    grep -q "interrupted" "$d/out/stderr" || fail "compile/$signal: no message on stderr"
  else
    wait "$pid"; fail "compile/$signal: no temporary file seen in the cache"
  fi
done

# 2. Interrupted while the CSV is written (its temporary file exists beside the output); the
# cache is warm, the run long enough to write for a while.
d=$work/csv; mkdir -p "$d/out"
NHC_CACHE_DIR=$d/cache "$nhc" simulate "$scene" >/dev/null 2>&1 || fail "warming the cache"
outputs=400000
start "$d/out" "$d/cache" --outputs "$outputs"
if wait_for_file "$d/out" 'out.csv.tmp*'; then
  kill -s INT "$pid"
  interrupted_exit INT 130 "csv"
  check_clean "csv" "$d/out" "$d/cache" "$outputs"
  [ ! -e "$d/out/out.csv" ] || fail "csv: the output exists after the interrupt"
else
  wait "$pid"; echo "note: the CSV was written before the interrupt could land" >&2
fi

# 3. SIGINT at a spread of moments over whole runs (deriving, compiling, integrating, writing),
# from an empty cache each time.
for delay in 0.01 0.03 0.06 0.1 0.15 0.2 0.3 0.5 0.8 1.2; do
  d=$work/at_$delay; mkdir -p "$d/out"
  start "$d/out" "$d/cache"
  sleep "$delay"
  kill -s INT "$pid" 2>/dev/null
  wait "$pid"; rc=$?
  [ "$rc" -eq 130 ] || [ "$rc" -eq 0 ] || fail "at $delay s: exit code $rc"
  check_clean "at $delay s" "$d/out" "$d/cache" 200
  # Whatever the cache holds is complete: a rerun uses it and succeeds.
  NHC_CACHE_DIR=$d/cache "$nhc" simulate "$scene" -o "$d/out/again.csv" >/dev/null 2>&1 ||
    fail "at $delay s: the rerun on the same cache failed"
  echo "interrupt at $delay s: exit $rc"
done

# 4. nhc compare, whose output is a directory built in a temporary sibling (atomic_directory.hpp):
# SIGINT while models are integrated or gnuplot draws leaves no temporary directory, and DIR is
# either absent or complete.
d=$work/compare; mkdir -p "$d"
for delay in 0.05 0.15 0.3 0.5 0.8; do
  rm -rf "$d/out"
  NHC_CACHE_DIR=$work/csv/cache "$nhc" compare "$scene" -o "$d/out" >"$d/stdout" 2>"$d/stderr" &
  pid=$!
  sleep "$delay"
  kill -s INT "$pid" 2>/dev/null
  wait "$pid"; rc=$?
  [ "$rc" -eq 130 ] || [ "$rc" -eq 0 ] || fail "compare at $delay s: exit code $rc"
  leftovers=$(find "$d" -name '*.tmp*' 2>/dev/null)
  [ -z "$leftovers" ] || fail "compare at $delay s: temporary files left: $leftovers"
  [ ! -e "$d/out" ] || [ -f "$d/out/compare.md" ] || fail "compare at $delay s: an incomplete directory"
  echo "compare interrupted at $delay s: exit $rc"
done

[ "$failures" -eq 0 ] && echo "interrupt test: no partial or temporary file after any interrupt"
exit $((failures > 0))
