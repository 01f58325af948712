#!/bin/sh
# --guess under the data-file rules (docs/safety.md, "Reading: limits"): a FIFO, a character device,
# a file over 64 MB, a NaN or infinite cell, a short row, control characters in a cell are exit 2
# in one line naming the file (and the line and column), nothing hangs or crashes; a CRLF file is read.
# nhc animate --path reads through the same reader: the same refusals.
# Usage: guess_files_test.sh NHC SCENE WORKDIR ANIMATED_SCENE
nhc=$1 scene=$2 d=$3 animated=$4
rm -rf "$d" && mkdir -p "$d" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
refused() {  # refused GUESS PATTERN: exit 2, one line matching PATTERN
  out=$(timeout 60 "$nhc" optimize "$scene" --intervals 10 --guess "$1" 2>&1 >/dev/null); rc=$?
  echo "$1 -> $rc: $out"
  test $rc -eq 2 || fail "$1: exit $rc, not 2"
  test "$(printf '%s\n' "$out" | wc -l)" -eq 1 || fail "$1: more than one line"
  printf '%s\n' "$out" | grep -q -- "$2" || fail "$1: no '$2'"
}
"$nhc" optimize "$scene" --intervals 10 -o "$d/good.csv" >/dev/null 2>&1 || fail "the first optimum"
mkfifo "$d/fifo.csv" && refused "$d/fifo.csv" "fifo.csv: error: is a FIFO"
refused /dev/zero "/dev/zero: error: is a character device"
truncate -s 65M "$d/big.csv" && refused "$d/big.csv" "big.csv: error: is 65 MB, more than the 64 MB"
head -1 "$d/good.csv" > "$d/nan_t.csv" && sed -n 2p "$d/good.csv" | sed 's/^[^,]*,/nan,/' >> "$d/nan_t.csv"
refused "$d/nan_t.csv" "nan_t.csv:2:1: error: 'nan' is not a finite number"
head -3 "$d/good.csv" | sed '3s/,[^,]*$/,inf/' > "$d/inf.csv" && refused "$d/inf.csv" "inf.csv:3:[0-9]*: error: 'inf' is not a finite number"
head -3 "$d/good.csv" | sed '3s/,[^,]*$//' > "$d/short.csv" && refused "$d/short.csv" "short.csv:3:1: error: 6 cells, the header has 7"
head -2 "$d/good.csv" > "$d/escape.csv" && printf '0.5,1\033[31m,0,0,0,0,0\n' >> "$d/escape.csv"
refused "$d/escape.csv" "escape.csv:3:5: error: '1\\\\x1b\[31m' is not a finite number"
sed 's/$/\r/' "$d/good.csv" > "$d/crlf.csv"
out=$("$nhc" optimize "$scene" --intervals 10 --guess "$d/crlf.csv" 2>/dev/null) || fail "the CRLF guess: exit $?"
echo "$out" | grep -q '^  cost = 3.14' || fail "the CRLF guess's cost"
for bad in "$d/fifo.csv" /dev/zero "$d/big.csv" "$d/nan_t.csv" "$d/escape.csv"; do
  out=$(timeout 60 "$nhc" animate "$animated" --path "$bad" -o "$d/page" 2>&1 >/dev/null); rc=$?
  echo "animate --path $bad -> $rc: $out"
  test $rc -eq 2 || fail "animate --path $bad: exit $rc"
  test ! -e "$d/page" || fail "animate --path $bad wrote a page"
  case $bad in *nan_t.csv) printf '%s\n' "$out" | grep -q "nan_t.csv:2:1: error: 'nan' is not a finite number" || fail "animate: the NaN";; esac
done
echo PASS
