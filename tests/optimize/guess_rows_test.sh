#!/bin/sh
# --guess rows against their header, without a solve before (so scripts/sanitize.sh runs it under
# AddressSanitizer): a one-row guess whose t is NaN or infinite, a row wider or narrower than its
# header, a header wider than its rows are exit 2 in one line at the file's line and column; a
# one-row guess with a finite t is a constant start that IPOPT takes (one iteration allowed: exit 3
# at the iteration limit, in words). Nothing crashes (a sanitizer's report is another exit status).
# Usage: guess_rows_test.sh NHC SCENE WORKDIR   (SCENE: examples/heisenberg_optimal.toml)
nhc=$1 scene=$2 d=$3
rm -rf "$d" && mkdir -p "$d" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
header="t,x,x',y,y',z,z'"
refused() {  # refused NAME ROW PATTERN [HEADER]
  printf '%s\n%s\n' "${4:-$header}" "$2" > "$d/$1.csv"
  out=$(timeout 120 "$nhc" optimize "$scene" --intervals 10 --guess "$d/$1.csv" 2>&1 >/dev/null); rc=$?
  echo "$1 -> $rc: $out"
  test $rc -eq 2 || fail "$1: exit $rc, not 2"
  test "$(printf '%s\n' "$out" | wc -l)" -eq 1 || fail "$1: more than one line"
  printf '%s\n' "$out" | grep -q -- "$3" || fail "$1: no '$3'"
}
refused nan_t "nan,0,0,0,0,0,0" "nan_t.csv:2:1: error: 'nan' is not a finite number"
refused inf_t "-inf,0,0,0,0,0,0" "inf_t.csv:2:1: error: '-inf' is not a finite number"
refused wide "0,0,0,0,0,0,0,0,0" "wide.csv:2:1: error: 9 cells, the header has 7"
refused narrow "0,0,0,0,0" "narrow.csv:2:1: error: 5 cells, the header has 7"
refused wide_header "0,0,0,0,0,0,0" "wide_header.csv:2:1: error: 7 cells, the header has 8" "$header,w"
printf '%s\n%s\n' "$header" "0.5,0,0,0,0,0,0" > "$d/one.csv"
out=$(timeout 120 "$nhc" optimize "$scene" --intervals 10 --max-iterations 1 --guess "$d/one.csv" 2>&1 >/dev/null); rc=$?
echo "one row -> $rc: $(printf '%s\n' "$out" | grep -v '^  iteration')"
test $rc -eq 3 || fail "one row: exit $rc, not 3"
printf '%s\n' "$out" | grep -q "IPOPT reached its iteration limit (1 iterations)" || fail "one row: not the iteration limit"
echo PASS
