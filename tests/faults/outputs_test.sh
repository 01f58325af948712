#!/usr/bin/env bash
# Outputs never replace inputs: every command refuses, with exit 2 naming
# both paths, an output that is the scene itself — by the same name, another spelling, a
# symbolic link or a hard link — and the scene is left byte for byte as it was.
# Usage: outputs_test.sh NHC SCENE WORK_DIR
nhc=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
export NHC_CACHE_DIR=$work/cache

S=$work/S.toml
cp "$scene" "$S"
ln -s "$S" "$work/symlink.csv"
ln "$S" "$work/hardlink.csv"
mkdir -p "$work/sub"
for output in "$S" "$work/sub/../S.toml" "$work/symlink.csv" "$work/hardlink.csv"; do
  for command in "simulate" "derive" "analyze" "report"; do
    run -- "$command" "$S" -o "$output"
    expect "$command -o $output" 2 "the output $output is the input $S (the same file)"
    cmp -s "$S" "$scene" || { fail "$command -o $output changed the scene"; cp "$scene" "$S"; }
    no_leftovers "$command -o $output" "$work"
  done
done
# Relative spellings from the scene's directory.
(cd "$work" && "$nhc" simulate S.toml -o ./S.toml >/dev/null 2>"$work/stderr"); rc=$?; err=$(cat "$work/stderr")
expect "simulate S.toml -o ./S.toml" 2 "is the input S.toml"
cmp -s "$S" "$scene" || fail "simulate S.toml -o ./S.toml changed the scene"
# Paths that are not what they seem: a directory where a file is expected, and the reverse.
run -- simulate "$S" -o "$work/sub"
expect "simulate -o DIRECTORY" 2 "the output $work/sub is a directory; a file name is expected"
run -- report "$S" -o "$work/hardlink.csv"
expect "report -o FILE" 2 "is the input"
touch "$work/plain"
run -- report "$S" -o "$work/plain"
expect "report -o FILE" 2 "the output $work/plain exists and is not a directory"
run -- simulate "$work/sub"
expect "simulate DIRECTORY" 2 "is a directory, not a scene file"
finish "outputs test"
