#!/usr/bin/env bash
# Failures that name their cause: a damaged result file is bad input, an absurd
# ensemble design is refused before it runs, a compiler out of memory is the environment, a run
# that never left t0 says so (and, at a singular point, why, in nhc analyze's words).
# Usage: failures_in_words_test.sh NHC KNIFE_EDGE_SCENE HOLDER_SINGULAR_SCENE WORK_DIR
nhc=$1 knife=$2 holder=$3 work=$4
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
export NHC_CACHE_DIR=$work/cache

# A real ensemble file, then damaged copies: truncated, and with its object headers overwritten
# (bytes 800 to 1400; damage in the data values themselves is not detectable without checksums).
run -- ensemble "$knife" --vary "m=1:2:4" -o "$work/ens.h5"
expect "a small ensemble" 0 ""
size=$(stat -c %s "$work/ens.h5")
head -c $((size / 2)) "$work/ens.h5" >"$work/truncated.h5"
cp "$work/ens.h5" "$work/overwritten.h5"
printf '%*s' 600 '' | tr ' ' '\377' | dd of="$work/overwritten.h5" bs=1 seek=800 conv=notrunc status=none
for damaged in truncated overwritten; do
  cp "$work/$damaged.h5" "$work/resume.h5"
  run -- ensemble "$knife" --vary "m=1:2:4" -o "$work/resume.h5" --resume
  [ "$rc" -eq 2 ] || fail "ensemble --resume on a $damaged file: exit $rc, expected 2; stderr: $err"
  grep -q "internal error\|bug in nhc" <<<"$err" && fail "ensemble --resume on a $damaged file: $err"
  run -- plot "$work/$damaged.h5" t_stop -o "$work/plot_$damaged"
  [ "$rc" -eq 2 ] || fail "plot of a $damaged file: exit $rc, expected 2; stderr: $err"
  grep -q "internal error\|bug in nhc" <<<"$err" && fail "plot of a $damaged file: $err"
done
run -- plot "$work/truncated.h5" t_stop -o "$work/plot_t"
expect "plot of a truncated file" 2 "$work/truncated.h5: error: the HDF5 file is damaged or truncated"

# A billion runs: refused before anything runs, naming the flag.
run -- ensemble "$knife" --vary "m=1:2:1000000000" -o "$work/huge.h5"
expect "a billion runs" 2 "--vary m=1:2:1000000000: error: "
grep -q "make the design smaller" <<<"$err" || fail "a billion runs: no advice: $err"
[ ! -e "$work/huge.h5" ] || fail "a billion runs: a file was written"

# The compiler out of memory: a compiler limited to 60 MB of address space.
printf '#!/bin/sh\nulimit -v 60000\nexec %s "$@"\n' "${CXX:-c++}" >"$work/small_cxx"
chmod +x "$work/small_cxx"
run NHC_CXX="$work/small_cxx" NHC_CACHE_DIR="$work/cache_small" -- simulate "$knife" -o "$work/k.csv"
expect "compiler out of memory" 4 "the C++ compiler ran out of memory compiling"
grep -q "bug in nhc" <<<"$err" && fail "compiler out of memory called a bug: $err"

# Singular at t0: never started, in the analysis' words.
run -- simulate "$holder" -o "$work/h.csv"
expect "singular at t0" 3 "the system Jacobian of the holder model is singular at t0 = 0"
grep -q "never started" <<<"$out" || fail "singular at t0: the summary does not say the run never started: $out"
grep -q "max drift\|reference error" <<<"$out" && fail "singular at t0: drifts reported for a run without samples: $out"
[ ! -e "$work/h.csv" ] || fail "singular at t0: a CSV was written"
# The same a second time (the scene cache must not hide the words).
run -- simulate "$holder" -o "$work/h.csv"
expect "singular at t0, again" 3 "the system Jacobian of the holder model is singular at t0 = 0"
# Memory limits from too small to enough: every run ends as bad input, the
# environment (out of memory, a thread refused) or success, never "internal error" nor an abort
# (a refused thread used to abort the ensemble with others still joinable). Below 96 MB the
# launcher refuses at once, in words (cli/launcher.cpp: between 38 and 41 MB the outcome used to
# move with each build — the loader failing, CLN's initializer aborting before main, OpenSSL
# failing as an "internal error" — a few hundred kB apart). Not under AddressSanitizer, which
# reserves terabytes of address space at start.
if ! ldd "$nhc" 2>/dev/null | grep -q asan; then
  particle_scene=$(dirname "$knife")/particle.toml
  NHC_CACHE_DIR="$work/cache_limits" "$nhc" ensemble "$particle_scene" --vary "q1'(0)=1:2:4" -o "$work/warm.h5" >/dev/null 2>&1
  for limit in 30000 40000 40500 50000 60000 65536 70000 80000 98304 100000 120000; do
    (ulimit -v $limit; NHC_CACHE_DIR="$work/cache_limits" "$nhc" ensemble "$particle_scene" --vary "q1'(0)=1:2:8" \
      --threads 2 -o "$work/limited.h5" >"$work/limited.out" 2>"$work/limited.err")
    code=$?
    case $code in
      0 | 2 | 4) ;;
      *) fail "ulimit -v $limit: exit $code: $(head -c 300 "$work/limited.err")" ;;
    esac
    if [ "$limit" -lt 98304 ]; then
      grep -q "below the 98304 kB nhc needs" "$work/limited.err" ||
        fail "ulimit -v $limit: not refused by the launcher: $(head -c 300 "$work/limited.err")"
    fi
    grep -q "internal error" "$work/limited.err" && fail "ulimit -v $limit: $(head -c 300 "$work/limited.err")"
  done
fi
finish "failures in words"
