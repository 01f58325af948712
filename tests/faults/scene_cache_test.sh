#!/usr/bin/env bash
# The scene-level cache (jit/nhc/jit/scene_cache.hpp) across processes: two `nhc simulate` at once
# on a cold cache and again on a warm one (same CSV, no warning, private entries, no temporary
# file, the warm runs say "(scene cache)"); a changed scene text, --set, --rtol or model is a miss
# and gives its own answer; NHC_SCENE_CACHE=off stores nothing; damaged entries are rebuilt with
# one warning each; `nhc report` reuses its derivation text. (That a warm build derives nothing
# is checked in-process: tests/jit/scene_cache_test.cpp.)
# Usage: scene_cache_test.sh NHC SCENE WORK_DIR   (SCENE: a scene with a parameter u, e.g.
# examples/particle_spring.toml)
nhc=$1 scene_in=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
export NHC_CACHE_DIR=$work/cache
scene=$work/scene.toml
cp "$scene_in" "$scene"
entries() { find "$NHC_CACHE_DIR/scenes" -name '*.entry' 2>/dev/null | wc -l; }

# Two at once, cold, then two at once, warm.
for phase in cold warm; do
  "$nhc" simulate "$scene" -o "$work/$phase-1.csv" >"$work/$phase-1.out" 2>"$work/$phase-1.err" &
  first=$!
  "$nhc" simulate "$scene" -o "$work/$phase-2.csv" >"$work/$phase-2.out" 2>"$work/$phase-2.err" &
  second=$!
  wait $first || fail "$phase run 1: exit code $?: $(cat "$work/$phase-1.err")"
  wait $second || fail "$phase run 2: exit code $?: $(cat "$work/$phase-2.err")"
  for k in 1 2; do
    cmp -s "$work/cold-1.csv" "$work/$phase-$k.csv" || fail "$phase run $k wrote another CSV"
    ! grep -q warning "$work/$phase-$k.err" || fail "$phase run $k warned: $(cat "$work/$phase-$k.err")"
    [ "$phase" = cold ] || grep -q "derive .* s (scene cache)" "$work/$phase-$k.out" ||
      fail "warm run $k did not use the scene cache: $(cat "$work/$phase-$k.out")"
  done
  [ "$(entries)" -eq 2 ] || fail "$phase: $(entries) scene cache entries, expected 2 (header, initial-point check)"
done
[ "$(stat -c %a "$NHC_CACHE_DIR/scenes")" = 700 ] || fail "the scenes directory is not private"
for e in "$NHC_CACHE_DIR"/scenes/*.entry; do
  [ "$(stat -c %a "$e")" = 600 ] || fail "$e has mode $(stat -c %a "$e"), expected 600"
done
no_leftovers "concurrent runs" "$NHC_CACHE_DIR" "$work"

# simulate_again DESCRIPTION EXPECTED(hit|miss) ARGS…: one run, its CSV in $work/last.csv.
simulate_again() {
  local what=$1 expected=$2; shift 2
  run -- simulate "$@" -o "$work/last.csv"
  expect "$what" 0 ""
  ! grep -q warning <<<"$err" || fail "$what: warned: $err"
  if grep -q "(scene cache)" <<<"$out"; then got=hit; else got=miss; fi
  [ "$got" = "$expected" ] || fail "$what: a scene-cache $got, expected a $expected"
}

simulate_again "--set u=0.5" miss "$scene" --set u=0.5
cp "$work/last.csv" "$work/set.csv"
cmp -s "$work/set.csv" "$work/cold-1.csv" && fail "--set u=0.5 gave the answer of u = 1"
simulate_again "--set u=0.5 again" hit "$scene" --set u=0.5
cmp -s "$work/last.csv" "$work/set.csv" || fail "--set u=0.5 from the cache gave another answer"
simulate_again "--rtol 1e-7" miss "$scene" --rtol 1e-7
simulate_again "--repair-initial" miss "$scene" --repair-initial
simulate_again "unchanged" hit "$scene"
cmp -s "$work/last.csv" "$work/cold-1.csv" || fail "the unchanged scene from the cache gave another answer"

# The text changed: a comment is a miss (same answer); a parameter is a miss with its own answer.
echo "# a comment" >>"$scene"
simulate_again "a comment added" miss "$scene"
cmp -s "$work/last.csv" "$work/cold-1.csv" || fail "a comment changed the answer"
simulate_again "a comment added, again" hit "$scene"
sed -i 's/^u = 1.0$/u = 0.5/' "$scene"
grep -q '^u = 0.5$' "$scene" || fail "the test could not change u in the scene"
simulate_again "u changed in the text" miss "$scene"
cmp -s "$work/last.csv" "$work/set.csv" || fail "u = 0.5 in the text and --set u=0.5 disagree"

# Turned off: nothing looked up, nothing stored.
before=$(entries)
echo "# another comment" >>"$scene"
run NHC_SCENE_CACHE=off -- simulate "$scene"
expect "NHC_SCENE_CACHE=off" 0 ""
! grep -q "(scene cache)" <<<"$out" || fail "NHC_SCENE_CACHE=off used the scene cache"
[ "$(entries)" -eq "$before" ] || fail "NHC_SCENE_CACHE=off stored entries"

# Damaged entries: every one rejected with one warning, rebuilt, then used again.
for e in "$NHC_CACHE_DIR"/scenes/*.entry; do head -c 100 "$e" >"$e.cut" && mv "$e.cut" "$e"; done
simulate_again_warned() {
  run -- simulate "$scene" -o "$work/last.csv"
  expect "damaged entries" 0 "rejected"
  [ "$(grep -c "scene cache entry .* rejected: .*; rebuilding it" <<<"$err")" -eq 2 ] ||
    fail "damaged entries: expected two warnings: $err"
  cmp -s "$work/last.csv" "$work/cold-1.csv" || fail "damaged entries: another answer"
}
cp "$scene_in" "$scene"  # the text of the first runs again
simulate_again_warned
simulate_again "after the damage" hit "$scene"

# nhc report: the derivation text is reused, the report's equations are the same.
report_flags=(--tolerances 1e-3:1e-4 --repeats 1 --jacobian dense --projection off --quiet)
run -- report "$scene" "${report_flags[@]}" -o "$work/report-cold"
expect "report, cold" 0 ""
before=$(entries)
run -- report "$scene" "${report_flags[@]}" -o "$work/report-warm"
expect "report, warm" 0 ""
[ "$(entries)" -eq "$before" ] || fail "the warm report stored new entries"
equations() { sed -n '/^## Equations/,$p' "$1/report.md"; }
[ -n "$(equations "$work/report-cold")" ] || fail "the report has no equations"
[ "$(equations "$work/report-cold")" = "$(equations "$work/report-warm")" ] ||
  fail "the warm report's equations differ from the cold one's"
finish "scene cache test"
