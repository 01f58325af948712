#!/usr/bin/env bash
# SIGINT and SIGTERM at each phase of a run — deriving, compiling, integrating, writing: nhc exits
# 128 + the signal, leaves no output, no partial file, no temporary file or directory, no cache
# entry half-made and no compiler running; the cache still works afterwards.
# Usage: signals_test.sh NHC SCENE KNIFE_CHAIN_SCRIPT WORK_DIR [LINEARIZE_SCENE]
nhc=$1 scene=$2 knife_chain=$3 work=$4 linearize_scene=${5:-}
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
set -m  # background jobs keep SIGINT (a script's background jobs otherwise ignore it)
python3 "$knife_chain" "$work" 8 1024 >/dev/null || fail "cannot write the knife-chain scenes"
big=$work/knife_chain_1024.toml  # deriving, analysing and generating take about two seconds
long=$work/knife_chain_8.toml    # integration to t = 5000 takes seconds

# start OUT_DIR CACHE ARGS…: nhc in the background, $pid.
start() {
  local out=$1 cache=$2; shift 2
  mkdir -p "$out"
  NHC_CACHE_DIR=$cache "$nhc" "$@" >"$out/stdout" 2>"$out/stderr" &
  pid=$!
}
# wait_for DIR PATTERN: until a path matching PATTERN exists under DIR (20 s), or nhc ended.
wait_for() {
  for _ in $(seq 1 2000); do
    [ -n "$(find "$1" -path "$2" 2>/dev/null | head -n 1)" ] && return 0
    kill -0 "$pid" 2>/dev/null || return 1
    sleep 0.01
  done
  return 1
}
# interrupt WHAT SIGNAL OUT CACHE: sends SIGNAL, checks the exit code and that nothing is left.
interrupt() {
  local what=$1 signal=$2 out=$3 cache=$4
  kill -s "$signal" "$pid"
  wait "$pid"; local rc=$?
  local expected=130; [ "$signal" = TERM ] && expected=143
  [ "$rc" -eq "$expected" ] || fail "$what: exit code $rc after SIG$signal, expected $expected"
  grep -q "interrupted" "$out/stderr" || fail "$what: no message"
  [ -z "$(find "$out" -name 'out*' -o -name 'report*' -o -name '*.hpp' 2>/dev/null)" ] || fail "$what: output left: $(ls "$out")"
  no_leftovers "$what" "$out" "$cache"
  local so
  for so in "$cache"/*.so; do
    [ -e "$so" ] || continue
    (cd "$cache" && sha256sum -c --quiet "$(basename "$so").sha256") || fail "$what: a cache entry without its digest"
  done
  pgrep -f "$cache/.*\.cpp\.tmp" >/dev/null && fail "$what: a compiler still runs"
  echo "$what: exit $rc"
}

# Deriving: nhc derive, and nhc simulate before anything is compiled.
start "$work/derive" "$work/derive/cache" generate "$big" -q -o "$work/derive"
sleep 0.4; interrupt "derive/INT" INT "$work/derive" "$work/derive/cache"
start "$work/derive_sim" "$work/derive_sim/cache" simulate "$big" -o "$work/derive_sim/out.csv"
sleep 0.4; interrupt "simulate while deriving/TERM" TERM "$work/derive_sim" "$work/derive_sim/cache"

# Compiling: the compiler's temporary source exists in the empty cache.
for signal in INT TERM; do
  d=$work/compile_$signal
  start "$d" "$d/cache" simulate "$scene" -o "$d/out.csv"
  if wait_for "$d/cache" '*.cpp.tmp*'; then
    interrupt "compile/$signal" "$signal" "$d" "$d/cache"
    # include/ holds the embedded C table for hand-written headers (complete, written atomically).
    [ -z "$(ls "$d/cache" | grep -vx include)" ] || fail "compile/$signal: the cache holds $(ls "$d/cache")"
  else
    wait "$pid"; fail "compile/$signal: the compiler was not seen running"
  fi
done

# Integrating: warm cache, a long integration.
d=$work/integrate
NHC_CACHE_DIR=$d/cache "$nhc" simulate "$long" >/dev/null 2>&1 || fail "warming the cache"
start "$d" "$d/cache" simulate "$long" --t-end 5000 -o "$d/out.csv"
sleep 0.8; interrupt "integrate/INT" INT "$d" "$d/cache"

# Writing: the CSV of nhc simulate, the directory of nhc report.
d=$work/write_csv
NHC_CACHE_DIR=$d/cache "$nhc" simulate "$scene" >/dev/null 2>&1 || fail "warming the cache"
start "$d" "$d/cache" simulate "$scene" --outputs 400000 -o "$d/out.csv"
if wait_for "$d" '*/out.csv.tmp*'; then interrupt "write CSV/INT" INT "$d" "$d/cache"
else wait "$pid"; echo "note: the CSV was written before the interrupt could land"; fi
d=$work/write_report
NHC_CACHE_DIR=$d/cache "$nhc" simulate "$scene" >/dev/null 2>&1 || fail "warming the cache"
start "$d" "$d/cache" report "$scene" --tolerances 1e-3:1e-6 --repeats 1 --quiet -o "$d/report"
if wait_for "$d" '*/report.tmp*/workprec.csv'; then interrupt "write report/TERM" TERM "$d" "$d/cache"
else wait "$pid"; fail "write report: the report's directory was not seen being written"; fi

# The directory of nhc linearize -o, while the sweep's files are written into it (gnuplot).
if [ -n "$linearize_scene" ]; then
  d=$work/write_linearize
  start "$d" "$d/cache" linearize "$linearize_scene" --sweep "ps'=0.5:6:12" -o "$d/lin"
  if wait_for "$d" '*/lin.tmp*'; then
    interrupt "write linearize/INT" INT "$d" "$d/cache"
    [ ! -e "$d/lin" ] || fail "write linearize: $d/lin left behind"
  else wait "$pid"; echo "note: the linearize directory was written before the interrupt could land"; fi
  rm -rf "$d/cache"  # no model is compiled by linearize: nothing to check below
fi

# Every cache is sound afterwards: a rerun reuses or rebuilds without a warning.
for cache in "$work"/*/cache; do
  NHC_CACHE_DIR=$cache "$nhc" simulate "$scene" >"$work/stdout" 2>"$work/stderr" || fail "rerun on $cache failed"
  [ -z "$(cat "$work/stderr")" ] || fail "rerun on $cache warned: $(cat "$work/stderr")"
done
finish "signals test"
