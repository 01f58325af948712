#!/usr/bin/env bash
# The hostile-input corpus (tests/fuzz/corpus/: every input the fuzzers found, the slow ones
# included; tests/bad/; the examples): `nhc derive` on each ends with exit 0 (derived), 2 (bad
# input, refused in words) or 3 (a mathematical failure), never a crash, an internal error or a
# hang. The time limit per input is a hang detector far above the few seconds any input takes
# (bench/corpus_times.sh measures them); it is not a speed test.
# Usage: corpus_test.sh NHC WORK_DIR
nhc=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
export NHC_CACHE_DIR=$work/cache
count=0
while IFS= read -r scene; do
  count=$((count + 1))
  timeout 120 "$nhc" derive "$scene" >"$work/stdout" 2>"$work/stderr"
  rc=$?
  case $rc in
    0 | 2 | 3) ;;
    124) fail "$scene: still running after 120 s" ;;
    *) fail "$scene: exit $rc: $(head -c 400 "$work/stderr")" ;;
  esac
  if [ "$rc" -eq 2 ] && ! head -n 1 "$work/stderr" | grep -qE '(^[^ ]+:[0-9]+:[0-9]+: error: |^[^ ]+: error: |^nhc: error: )'; then
    fail "$scene: exit 2 without a located one-line error: $(head -c 300 "$work/stderr")"
  fi
done < <("$(dirname "$0")/../../scripts/corpus_inputs.sh" "$work/scenes")
[ "$count" -gt 150 ] || fail "only $count corpus inputs found"
finish "corpus ($count inputs)"
