#!/usr/bin/env bash
# The fuzz stage's replay of the corpus through the symbolic stages: every input of
# scripts/corpus_inputs.sh (tests/fuzz/corpus/, tests/bad/, the examples) goes through
# nhc_derive_replay (tests/fuzz/derive_replay.cpp: load, derive, print, reduce, generate, under the
# work budget asked for cooperatively, without the command line's watchdog), each with a limit of
# processor time (ulimit -t: the same verdict on a loaded machine as on an idle one) and of memory
# (ulimit -v), with a wall-clock hang detector far beyond. An input that runs past a limit, or ends
# with another exit than 0, 2 or 3, fails the run with its file named: one GiNaC call that the predictions of work_budget.hpp let grow for
# seconds is a bug even where the command line's watchdog would stop it.
# Usage: replay_derive.sh NHC_DERIVE_REPLAY WORK_DIR [SECONDS [MEGABYTES]]
# NHC_REPLAY_WORK_SECONDS: the replay's work budget (default the command line's, 4 s); raised above
# SECONDS it lets a slow input run into the time limit, to try the stage on a planted one.
set -uo pipefail
replay=$1 work=$2 seconds=${3:-10} megabytes=${4:-2048}
root=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work" && mkdir -p "$work"
status=0 count=0 slowest=0 slowest_scene=
while IFS= read -r scene; do
  count=$((count + 1))
  start=$(date +%s%N)
  (
    ulimit -S -t "$seconds"  # soft: SIGXCPU (exit 152), where a hard limit would be SIGKILL
    ulimit -v $((megabytes * 1024))
    exec timeout -s KILL $((seconds * 30)) "$replay" "$scene" ${NHC_REPLAY_WORK_SECONDS:+"$NHC_REPLAY_WORK_SECONDS"}
  ) >"$work/stdout" 2>"$work/stderr"
  rc=$?
  elapsed=$((($(date +%s%N) - start) / 1000000))
  if [ "$elapsed" -gt "$slowest" ]; then slowest=$elapsed slowest_scene=$scene; fi
  case $rc in
    0 | 2 | 3) ;;
    152)  # SIGXCPU: the processor-time limit
      echo "replay: $scene: still running after $seconds s of processor time" >&2
      status=1 ;;
    137)  # the wall-clock hang detector (30 times the limit: a loaded machine is slow, not wrong)
      echo "replay: $scene: still running after $((seconds * 30)) s of wall time" >&2
      status=1 ;;
    *)
      echo "replay: $scene: exit $rc: $(head -c 400 "$work/stderr")" >&2
      status=1 ;;
  esac
done < <("$root/scripts/corpus_inputs.sh" "$work/scenes")
echo "replay: $count corpus inputs through derive and generate, at most $seconds s of processor time and" \
  "$megabytes MB each; slowest $((slowest / 1000)).$(printf '%03d' $((slowest % 1000))) s (wall): $slowest_scene"
exit $status
