#!/usr/bin/env bash
# Parameters no equation reads do not reach the generated code (item 10: 1.4 million
# unused parameters made a 68 MB shared object). A scene with 20000 of them: the header names only
# the two the model reads and stays small; --set of one that only an output uses still reaches
# the output; varying or sweeping one, or asking its sensitivities, is refused in words.
# Usage: unused_parameters_test.sh NHC WORK_DIR
nhc=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
export NHC_CACHE_DIR=$work/cache
scene=$work/unused.toml
{
  printf 'name = "unused_parameters"\ncoordinates = ["x"]\n'
  printf 'lagrangian = "m*x'"'"'^2/2 - k*x^2/2"\n[parameters]\nm = 1.0\nk = 4.0\n'
  for ((i = 0; i < 20000; ++i)); do printf 'u%d = %d.5\n' "$i" "$i"; done
  printf '[initial]\nx = [1.0, 0.0]\n[simulate]\nt_end = 1.0\n[outputs]\nshifted = "x + u7"\n'
} >"$scene"

run -- generate "$scene" -q -o "$work/generated"
expect "generate" 0 ""
header=$work/generated/unused_parameters_chetaev.hpp
grep -qF 'parameter_names[n_parameters] = {"k", "m"}' "$header" ||
  fail "the header does not name exactly k and m: $(grep -F 'parameter_names' "$header")"
size=$(stat -c %s "$header")
[ "$size" -lt 20000 ] || fail "the header has $size bytes: unused parameters reached it"

# x(t) = cos(2t) with k = 4, m = 1; the output adds u7 as --set gives it.
run -- simulate "$scene" --set u7=100 --t-end 1 -o "$work/out.csv"
expect "simulate --set of an unused parameter" 0 ""
awk -F, 'END { want = cos(2) + 100; d = $NF - want; if (d < 0) d = -d; exit !(d < 1e-5) }' "$work/out.csv" ||
  fail "the output x + u7 at t = 1 is $(tail -1 "$work/out.csv" | awk -F, '{print $NF}'), not cos(2) + 100"

run -- simulate "$scene" --sensitivity u3 -o "$work/s.csv"
expect "--sensitivity of an unused parameter" 2 "--sensitivity: error: the chetaev model's equations do not contain the parameter 'u3'"
run -- ensemble "$scene" --vary u3=1:2:3 -o "$work/e.h5"
expect "--vary of an unused parameter" 2 "--vary u3=1:2:3: error: the chetaev model's equations do not contain the parameter 'u3'"
finish "unused-parameters test"
