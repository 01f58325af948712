#!/usr/bin/env bash
# `mpirun --oversubscribe -np 2 nhc ensemble …` and one process (two threads) write the same
# FILE.h5, apart from timings (/runs/seconds, the wall_seconds attribute) and placement
# (/runs/rank, the ranks and threads attributes): a grid with trajectories, a random sample, and a
# grid with failing runs. Usage: mpi_matches_single_process.sh MPIEXEC NHC H5_SAME SCENE WORK_DIR
set -euo pipefail
mpiexec=$1 nhc=$2 same=$3 scene=$4 work=$5
rm -rf "$work" && mkdir -p "$work" && cd "$work"
export NHC_CACHE_DIR=$work/cache
as_root=()
[ "$(id -u)" -ne 0 ] || as_root=(--allow-run-as-root)
ignore=(--ignore /runs/seconds --ignore /runs/rank --ignore /@ranks --ignore /@threads --ignore /@wall_seconds)

compare() {
  local name=$1
  shift
  "$nhc" ensemble "$scene" "$@" --threads 2 -o "$name-single.h5" > "$name-single.log"
  "$mpiexec" --oversubscribe "${as_root[@]}" -np 2 "$nhc" ensemble "$scene" "$@" -o "$name-mpi.h5" > "$name-mpi.log"
  grep -q "on 2 ranks x 1 thread" "$name-mpi.log" || { echo "FAIL $name: not run on 2 ranks"; cat "$name-mpi.log"; exit 1; }
  grep -q "on 1 rank x 2 threads" "$name-single.log" || { echo "FAIL $name: not run on 2 threads"; exit 1; }
  echo "== $name"
  "$same" "$name-single.h5" "$name-mpi.h5" "${ignore[@]}"
  # Not vacuous: the files differ where they should (timings).
  if "$same" "$name-single.h5" "$name-mpi.h5" > /dev/null; then echo "FAIL $name: timings identical?"; exit 1; fi
}

compare grid --vary "x'(0)=0.5:2:12" --vary b=0.2:2:10 --keep trajectories --outputs 20
# Both ranks ran some of the grid (small ensembles may all go to rank 0's thread while rank 1 starts).
grep -Eq "runs per rank: [1-9][0-9]*, [1-9]" grid-mpi.log || { echo "FAIL grid: a rank ran nothing"; exit 1; }
compare sample --sample "b=uniform(0.1,2)" --sample "x'(0)=normal(1,0.2)" --samples 60 --seed 7
compare failures --vary m=-1:1:9 --t-end 0.05
echo "PASS"
