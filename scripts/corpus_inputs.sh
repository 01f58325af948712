#!/usr/bin/env bash
# Lists the scene inputs of the hostile-input corpus, one path per line, writing a scene around
# every expression input of the expression fuzzer (as the Lagrangian of a two-coordinate
# system) into DIR. Shared by tests/faults/corpus_test.sh (exit codes) and bench/corpus_times.sh
# (times).
# Usage: scripts/corpus_inputs.sh DIR
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=$1
mkdir -p "$dir"
ls "$root"/tests/fuzz/corpus/scene/* "$root"/tests/bad/*.toml "$root"/examples/*.toml
for f in "$root"/tests/fuzz/corpus/expression/*; do
  # A TOML literal string holds any text but its own delimiter and control characters.
  if grep -q "'''" "$f" || LC_ALL=C grep -q '[[:cntrl:]]' <(tr -d '\n' <"$f"); then continue; fi
  scene="$dir/expression_$(basename "$f").toml"
  {
    echo 'name = "expression_input"'
    echo 'coordinates = ["x", "y"]'
    printf "lagrangian = '''%s'''\n" "$(cat "$f")"
    echo 'constraints = ["x'"'"' - y"]'
    echo '[parameters]'
    echo 'm = 1.0'
    echo 'g = 9.81'
    echo '[initial]'
    echo 'x = [0.1, 1.0]'
    echo 'y = [0.2, 0.0]'
  } >"$scene"
  echo "$scene"
done
