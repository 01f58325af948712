#!/usr/bin/env bash
# --backend and $NHC_BACKEND (docs/interpreter.md): auto runs a model never compiled through the
# interpreter, so no compiler is needed; compiled needs one (exit 4 without); interpreted and
# compiled write the same CSV; an unknown backend is exit 2 naming the flag or the variable.
# Usage: backend_test.sh NHC SCENE WORK_DIR
set -euo pipefail
nhc=$1
scene=$2
work=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
cd "$work"
export NHC_CACHE_DIR="$work/cache"
unset NHC_BACKEND

status() { set +e; "$@" > out.txt 2> err.txt; echo $?; set -e; }

[ "$(status env NHC_CXX="$work/no-such-compiler" "$nhc" simulate "$scene" -o auto.csv)" = 0 ] ||
  fail "auto without a compiler: $(cat err.txt)"
grep -q "interpreted (no compile)" out.txt || fail "auto did not say it ran interpreted: $(cat out.txt)"
[ "$(status env NHC_CXX="$work/no-such-compiler" "$nhc" simulate "$scene" --backend compiled)" = 4 ] ||
  fail "--backend compiled without a compiler is not exit 4"
[ "$(status env NHC_CXX="$work/no-such-compiler" NHC_BACKEND=compiled "$nhc" simulate "$scene")" = 4 ] ||
  fail "NHC_BACKEND=compiled without a compiler is not exit 4"

[ "$(status "$nhc" simulate "$scene" --backend compiled -o compiled.csv)" = 0 ] || fail "compiled: $(cat err.txt)"
grep -q "compile .* s" out.txt || fail "compiled did not say it compiled: $(cat out.txt)"
[ "$(status "$nhc" simulate "$scene" --backend interpreted -o interpreted.csv)" = 0 ] || fail "interpreted: $(cat err.txt)"
cmp -s compiled.csv interpreted.csv || fail "interpreted and compiled CSVs differ"
cmp -s compiled.csv auto.csv || fail "auto and compiled CSVs differ"
# Compiled once: auto now takes the compiled model.
[ "$(status "$nhc" simulate "$scene")" = 0 ] || fail "auto after a compile: $(cat err.txt)"
grep -q "(cached)" out.txt || fail "auto did not take the compiled model: $(cat out.txt)"

[ "$(status "$nhc" simulate "$scene" --backend jit)" = 2 ] || fail "--backend jit is not exit 2"
grep -q -- "--backend" err.txt || fail "--backend jit: $(cat err.txt)"
[ "$(status env NHC_BACKEND=jit "$nhc" simulate "$scene")" = 2 ] || fail "NHC_BACKEND=jit is not exit 2"
grep -q "NHC_BACKEND" err.txt || fail "NHC_BACKEND=jit: $(cat err.txt)"
[ "$(wc -l < err.txt)" = 1 ] || fail "more than one line: $(cat err.txt)"
echo ok
