#!/bin/sh
# The snakeboard of examples/snakeboard_move.toml at 160 intervals from the default start
# (continuation 10, 40, 160): wall time, exit status and the reported path error
# (docs/optimize.md, "Mesh refinement"). Usage: bench/optimize_snakeboard.sh BUILD_DIR
build=${1:-build}
here=$(dirname "$0")
start=$(date +%s.%N)
out=$("$build/cli/nhc" optimize "$here/../examples/snakeboard_move.toml" --intervals 160 2>/dev/null)
rc=$?
end=$(date +%s.%N)
echo "$out" | grep -E 'round|cost =|path error ='
echo "exit $rc, wall time $(echo "$end - $start" | bc) s"
