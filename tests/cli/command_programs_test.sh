#!/usr/bin/env bash
# The commands of command_programs.hpp run in programs of their own: nhc-main loads neither HDF5,
# Open MPI nor IPOPT; `nhc` and `nhc-main` start nhc-ensemble and nhc-optimize for their
# commands, with the same arguments; a missing program is exit 4 in words.
# Usage: command_programs_test.sh NHC WORK_DIR
set -euo pipefail
nhc=$1
work=$2
dir=$(dirname "$nhc")
fail() { echo "FAIL: $*" >&2; exit 1; }

libraries=$(ldd "$dir/nhc-main")
if grep -E -i 'hdf5|libmpi|open-rte|open-pal|ipopt|mumps' <<< "$libraries"; then
  fail "nhc-main loads the libraries of ensemble, plot or optimize"
fi
grep -q hdf5 <<< "$(ldd "$dir/nhc-ensemble")" || fail "nhc-ensemble does not load HDF5"
grep -q ipopt <<< "$(ldd "$dir/nhc-optimize")" || fail "nhc-optimize does not load IPOPT"

help=$("$nhc" --help)
for command in ensemble plot optimize derive simulate; do
  grep -q "^  $command " <<< "$help" || fail "nhc --help does not list $command"
done
# Each command's own help, through the launcher and through nhc-main.
for program in "$nhc" "$dir/nhc-main"; do
  grep -q -- "--vary" <<< "$("$program" ensemble --help)" || fail "$program ensemble --help is not the ensemble's"
  grep -q "OUTCOME" <<< "$("$program" plot --help)" || fail "$program plot --help is not the plot's"
  grep -q -- "--intervals" <<< "$("$program" optimize --help)" || fail "$program optimize --help is not the optimize's"
done
# Exit codes and words come from the started program: a bad flag is exit 2.
set +e
"$nhc" optimize --no-such-flag > /dev/null 2> err.txt
status=$?
set -e
[ "$status" = 2 ] || fail "nhc optimize --no-such-flag exited $status, not 2"

# Without nhc-ensemble beside it: exit 4, naming the program.
rm -rf "$work"
mkdir -p "$work"
cp "$nhc" "$dir/nhc-main" "$work/"
for program in "$work/nhc" "$work/nhc-main"; do
  set +e
  "$program" plot results.h5 t_stop > /dev/null 2> "$work/err.txt"
  status=$?
  set -e
  [ "$status" = 4 ] || fail "$program plot without nhc-ensemble exited $status, not 4"
  grep -q "nhc-ensemble" "$work/err.txt" || fail "$program plot without nhc-ensemble said: $(cat "$work/err.txt")"
  [ "$(wc -l < "$work/err.txt")" = 1 ] || fail "more than one line: $(cat "$work/err.txt")"
done
echo "ok"
