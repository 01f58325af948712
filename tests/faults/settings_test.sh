#!/usr/bin/env bash
# Settings the arithmetic cannot honour and paths that are not what they seem get a located,
# truthful message and exit 2, before anything is compiled or written.
# Usage: settings_test.sh NHC SCENE WORK_DIR
nhc=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
export NHC_CACHE_DIR=$work/cache

run -- simulate "$scene" --rtol 1e-20
expect "--rtol 1e-20" 2 "--rtol: error: --rtol 1e-20 is below the double-precision machine epsilon"
run -- simulate "$scene" --atol 0
expect "--atol 0" 2 "--atol"
run -- report "$scene" --tolerances 1e-10:1e-17 -o "$work/r"
expect "--tolerances to 1e-17" 2 "--tolerances: error: --tolerances 1e-10:1e-17: rtol 1e-16 is below"
run -- report "$scene" --reference-rtol 1e-18 -o "$work/r"
expect "--reference-rtol 1e-18" 2 "--reference-rtol: error"
# In the scene: FILE:LINE:COLUMN of the value.
sed 's/^\[simulate\]$/[simulate]\nrtol = 1e-17/' "$scene" >"$work/tiny_rtol.toml"
line=$(grep -n '^rtol = 1e-17' "$work/tiny_rtol.toml" | cut -d: -f1)
run -- simulate "$work/tiny_rtol.toml"
expect "[simulate] rtol = 1e-17" 2 "$work/tiny_rtol.toml:$line:8: error: rtol = 1e-17 is below"
sed 's/^\[simulate\]$/[simulate]\natol = 0.0/' "$scene" >"$work/zero_atol.toml"
run -- simulate "$work/zero_atol.toml"
expect "[simulate] atol = 0" 2 "error: atol must be positive"
run NHC_COMPILE_TIMEOUT=-1 -- simulate "$scene"
expect "NHC_COMPILE_TIMEOUT=-1" 2 "NHC_COMPILE_TIMEOUT: error: '-1' is not a number of seconds"
run -- simulate "$work"
expect "a directory as the scene" 2 "is a directory, not a scene file"
[ ! -e "$work/r" ] || fail "an output was written despite the refusal"
[ ! -e "$work/cache" ] || fail "something was compiled despite the refusal"
finish "settings test"
