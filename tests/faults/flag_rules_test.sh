#!/usr/bin/env bash
# One rule per kind of flag (cli/flag_rules.hpp), the same in every command that has the flag:
# NaN, infinity, zero and tolerances below the machine epsilon are exit 2 in the same words,
# naming the flag, before anything is compiled or written; list flags refuse duplicates; counts
# are bounded; no message prints DBL_MAX's 309 digits.
# Usage: flag_rules_test.sh NHC SOURCE_DIR WORK_DIR
nhc=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
export NHC_CACHE_DIR=$work/cache
particle=$src/examples/particle.toml
heisenberg=$src/examples/heisenberg.toml

# flag VALUE WORDS: every command with the flag refuses VALUE with "FLAG: error: FLAG VALUE WORDS".
refused_everywhere() {
  local flag=$1 value=$2 words=$3
  local -a commands=(
    "simulate $particle"
    "compare $particle -o $work/out"
    "connect $heisenberg --to x=1,y=0,z=0.25 --t-end 1"
    "ensemble $particle --vary m=1:2:2 -o $work/out.h5"
    "report $particle -o $work/out"
  )
  for c in "${commands[@]}"; do
    # shellcheck disable=SC2086
    run -- $c "$flag" "$value"
    [ "$rc" -eq 0 ] && [ "$flag" = --atol-scale ] && continue
    case "$c:$flag" in report*:--rtol | report*:--atol | connect*:--t-end | report*:--tolerance | simulate*:--tolerance | ensemble*:--tolerance) continue ;; esac
    if grep -q "requires\|was not expected\|The following argument" <<<"$err"; then continue; fi   # no such flag here
    expect "${c%% *} $flag $value" 2 "$flag: error: $flag $value $words"
    checked=$((checked + 1))
  done
}
checked=0
refused_everywhere --rtol nan "is not a positive number"
refused_everywhere --atol nan "is not a positive number"
refused_everywhere --rtol 1e-17 "is below the double-precision machine epsilon"
refused_everywhere --rtol -1 "is not a positive number"
refused_everywhere --rtol 1e10 "is not below 1"
refused_everywhere --atol inf "is not a positive number"
refused_everywhere --t-end nan "is not a finite number"
refused_everywhere --outputs 0 "is not a whole number from 1 to 10000000"
refused_everywhere --outputs 100000000 "is not a whole number from 1 to 10000000"
refused_everywhere --tolerance nan "is not a positive number"
# --rtol (4 values) and --atol (2) in simulate, compare, connect, ensemble: 24; --t-end in
# simulate, compare, ensemble, report: 4; --outputs (2) in all five: 10; --tolerance in compare
# and connect: 2.
[ "$checked" -eq 40 ] || fail "only $checked command-flag pairs were checked"

run -- report "$particle" --atol-scale nan -o "$work/out"
expect "report --atol-scale nan" 2 "--atol-scale: error: --atol-scale nan is not a positive number"
run -- report "$particle" --reference-rtol nan -o "$work/out"
expect "report --reference-rtol nan" 2 "--reference-rtol: error: --reference-rtol nan is not a positive number"
run -- connect "$heisenberg" --to x=1,y=0,z=0.25 --t-end 1 --max-iterations 0
expect "connect --max-iterations 0" 2 "--max-iterations: error: --max-iterations 0 is not a whole number from 1 to 10000"
run -- ensemble "$particle" --vary m=1:2:2 --checkpoint-every nan -o "$work/out.h5"
expect "ensemble --checkpoint-every nan" 2 "--checkpoint-every: error: --checkpoint-every nan is not a positive number"
run -- simulate "$particle" --outputs 1e3
expect "simulate --outputs 1e3" 2 "--outputs: error: --outputs '1e3' is not a whole number"

# Output times: t_end near DBL_MAX keeps every row; times that collapse in floating point are refused.
run NHC_CACHE_DIR="$work/cache_far" -- simulate "$src/examples/knife_edge.toml" --t-end 1e308 -o "$work/far.csv"
expect "simulate --t-end 1e308" 0 ""
[ "$(wc -l < "$work/far.csv")" -eq 202 ] || fail "--t-end 1e308: $(wc -l < "$work/far.csv") lines, want 202"
rm -f "$work/far.csv"
sed -e 's/^t0 = .*/t0 = 1e12/' -e 's/^t_end = .*/t_end = 1000000000001.0/' "$src/examples/knife_edge.toml" > "$work/late.toml"
for c in simulate "compare -o $work/out" "report -o $work/out" "ensemble --vary m=1:2:2 -o $work/out.h5"; do
  # shellcheck disable=SC2086
  run -- ${c%% *} "$work/late.toml" ${c#* } --outputs 10000000
  [ "$c" = simulate ] && run -- simulate "$work/late.toml" --outputs 10000000
  expect "${c%% *}: collapsing output times" 2 "--t-end/--outputs: error: 10000000 output intervals from t0 = 1000000000000 to t_end = 1000000000001 are closer than double precision resolves"
done

# report --sweep: the range is checked before any run (1e-155:1e155 overflowed hi/lo and crashed
# in write_report, leaving its temporary directory); a bad value names --sweep.
run -- report "$src/examples/knife_edge.toml" --sweep m=1e-155:1e155 -o "$work/out"
expect "report --sweep m=1e-155:1e155" 2 "--sweep: error: --sweep 1e155:1e-155: more than 20 decades"
run -- report "$src/examples/knife_edge.toml" --sweep m=abc -o "$work/out"
expect "report --sweep m=abc" 2 "--sweep: error: --sweep abc: 'abc' is not a positive number"
no_leftovers "report --sweep" "$work"

# Empty values are refused, not taken as the flag's absence.
run -- simulate "$particle" --output-times '' -o "$work/out.csv"
expect "simulate --output-times ''" 2 "--output-times: error: --output-times '' is an empty value"
run -- simulate "$particle" -o ''
expect "simulate -o ''" 2 "--output: error: --output '' is an empty value"
# --flag= with nothing after the '=' took the next argument as its value (--t-end= -o out.csv read
# -o as the time; --models= chetaev compared chetaev).
run -- simulate "$particle" --t-end= -o "$work/out.csv"
expect "simulate --t-end=" 2 "--t-end: error: --t-end '' is an empty value"
run -- compare "$particle" --models= chetaev -o "$work/out"
expect "compare --models=" 2 "--models: error: --models '' is an empty value"
run -- ensemble "$particle" --vary "q1'(0)=1:2:3" --threads= 2 -o "$work/out.h5"
expect "ensemble --threads=" 2 "--threads: error: --threads '' is an empty value"
# A missing file is named as missing, not as "not an HDF5 file".
run -- plot "$work/missing.h5" final:q1
expect "plot of a missing file" 2 "$work/missing.h5: error: cannot read an HDF5 file: No such file or directory"

# Missing parent directories: created for files and directories alike (parent_directories.hpp).
run NHC_CACHE_DIR="$work/cache_parents" -- connect "$heisenberg" --to x=1,y=0,z=0.25 --t-end 1 -o "$work/parents/a/x.csv"
expect "connect -o into a missing directory" 0 ""
[ -f "$work/parents/a/x.csv" ] || fail "connect did not write into a missing directory"
run NHC_CACHE_DIR="$work/cache_parents" -- simulate "$particle" -o "$work/parents/b/c/p.csv"
expect "simulate -o into a missing directory" 0 ""
[ -f "$work/parents/b/c/p.csv" ] || fail "simulate did not write into a missing directory"
rm -rf "$work/parents"

# A model's own requirements (suslov: a dependent coordinate per constraint): exit 2 at the scene
# in every command, as simulate (connect answered exit 3).
nod=$src/tests/faults/suslov_without_dependent.toml
for c in "simulate" "connect --to x=1 --t-end 1" "linearize" "report -o $work/out" "ensemble --vary x'(0)=0:1:2 -o $work/out.h5"; do
  # shellcheck disable=SC2086
  run -- ${c%% *} "$nod" --model suslov ${c#* }
  [ "$c" = simulate ] && run -- simulate "$nod" --model suslov
  [ "$c" = linearize ] && run -- linearize "$nod" --model suslov
  expect "${c%% *} --model suslov without dependent" 2 "suslov_without_dependent.toml:6:15: error: the suslov model needs one dependent coordinate per constraint"
done

# --threads beyond the machine: capped at its cores and at the runs (100000 threads aborted).
run NHC_CACHE_DIR="$work/cache_threads" -- ensemble "$particle" --vary "q1'(0)=1:2:3" --threads 100000 -o "$work/threads.h5"
expect "ensemble --threads 100000" 0 "nhc ensemble: --threads 100000 capped at the "
rm -f "$work/threads.h5"

# Ensemble memory and disk estimated before anything runs: 4000 runs of 10^7 kept outputs (before:
# std::bad_alloc after the runs had started).
run -- ensemble "$particle" --vary "q1'(0)=1:2:4000" --keep trajectories --outputs 10000000 -o "$work/out.h5"
expect "ensemble --keep trajectories --outputs 10000000" 2 "4000 runs would "

# Duplicates in list flags.
run -- compare "$src/examples/appell_hamel.toml" --models chetaev,chetaev -o "$work/out"
expect "compare --models chetaev,chetaev" 2 "--models: error: model 'chetaev' is given twice"
run -- linearize "$src/tests/linearize/scenes/rolling_disk.toml" --at "ps'=5" --at "ps'=6"
expect "linearize --at twice" 2 "--at: error: the value of 'ps'' is given twice"

# No bound printed in 309 digits.
run -- simulate "$particle" --rtol -1
grep -q '[0-9]\{40\}' <<<"$err" && fail "a 40-digit number in: $err"

[ ! -e "$work/out" ] && [ ! -e "$work/out.h5" ] || fail "an output was written despite a refusal"
[ ! -e "$work/cache" ] || fail "something was compiled despite a refusal"
echo "checked $checked command-flag pairs"; finish "flag rules test"
