#!/usr/bin/env bash
# Start-up cost of the nhc command: processor and wall time of `nhc --version` and
# `nhc derive examples/particle.toml` (perf stat, repeated), and the shared libraries each program
# loads. Given a second nhc (a build of another commit), both side by side in one table.
# Usage: bench/startup.sh NHC [BEFORE_NHC]   (prints Markdown on stdout)
set -euo pipefail
cd "$(dirname "$0")/.."
measure() {  # NHC ARGS... -> "task-clock-ms wall-ms"
  local out
  out=$(perf stat -x, -r "$repeat" -e task-clock "$@" 2>&1 >/dev/null | grep task-clock)
  local task wall
  task=$(cut -d, -f1 <<< "$out")
  local start end
  start=$(date +%s.%N)
  for _ in $(seq "$repeat"); do "$@" > /dev/null; done
  end=$(date +%s.%N)
  wall=$(awk -v s="$start" -v e="$end" -v n="$repeat" 'BEGIN{printf "%.1f", (e-s)*1000/n}')
  printf "%.1f ms | %s ms" "$task" "$wall"
}
libraries() { ldd "$(dirname "$1")/$2" 2>/dev/null | wc -l; }
repeat=${NHC_STARTUP_REPEAT:-30}
command -v perf > /dev/null || { echo "bench/startup.sh: perf (Debian linux-perf) is missing" >&2; exit 4; }
echo "| nhc | command | processor time | wall time (mean of $repeat) | libraries of the program |"
echo "|---|---|---|---|---|"
for nhc in "$@"; do
  "$nhc" derive examples/particle.toml > /dev/null  # the scene cache warm, as in everyday use
  echo "| \`$nhc\` | \`nhc --version\` | $(measure "$nhc" --version) | nhc-main: $(libraries "$nhc" nhc-main) |"
  echo "| \`$nhc\` | \`nhc derive examples/particle.toml\` | $(measure "$nhc" derive examples/particle.toml) | |"
  for program in nhc-ensemble nhc-optimize; do
    [ -x "$(dirname "$nhc")/$program" ] && echo "| \`$nhc\` | ($program) | | | $program: $(libraries "$nhc" $program) |"
  done
done
