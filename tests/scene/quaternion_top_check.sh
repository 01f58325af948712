#!/bin/sh
# The tumbling top of examples/tumbling_top_quaternion.toml against its closed form
# (docs/quaternions.md) with --project: the quaternion within 1e-8 of q(t) component by component,
# its norm within 1e-10 of 1, energy and the spin Om3 conserved, and the attitudes where z-x-z
# angles are singular passed: upright (R33 = 1) at t = 0 and again after each precession period;
# with --set s=0 (end over end) upside down (R33 = -1) on the way.
# Usage: quaternion_top_check.sh NHC SCENE WORKDIR
set -eu
nhc=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
check() {  # check CSV: the limits on every row, and the extremes of R33 (axis_z) the run must reach
  awk -F, -v want_min="$2" -v want_max="$3" '
    NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
    { for (k = 0; k < 4; ++k) { e = $(col["error:q" k]); if (e < 0) e = -e; if (e > err) err = e }
      n = $(col["unit"]); if (n < 0) n = -n; if (n > norm) norm = n
      if (NR == 2) { e0 = $(col["invariant:energy"]); s0 = $(col["invariant:spin"]) }
      de = $(col["invariant:energy"]) - e0; if (de < 0) de = -de; if (de > dE) dE = de
      ds = $(col["invariant:spin"]) - s0; if (ds < 0) ds = -ds; if (ds > dS) dS = ds
      z = $(col["axis_z"]); if (NR == 2 || z < zmin) zmin = z; if (NR > 20 && z > zmax) zmax = z }
    END {
      printf "%s: max |q - closed form| %.3g, max ||q|^2 - 1| %.3g, energy drift %.3g, spin drift %.3g, R33 in [%.12f, %.12f] after t0\n", FILENAME, err, norm, dE, dS, zmin, zmax
      bad = 0
      if (!(err <= 1e-8)) { print "quaternion off its closed form"; bad = 1 }
      if (!(norm <= 1e-10)) { print "quaternion norm off 1"; bad = 1 }
      if (!(dE <= 1e-9 && dS <= 1e-9)) { print "energy or spin not conserved"; bad = 1 }
      if (want_min != "" && !(zmin <= want_min)) { print "never upside down"; bad = 1 }
      if (want_max != "" && !(zmax >= want_max)) { print "never upright again"; bad = 1 }
      exit bad
    }' "$1"
}
"$nhc" simulate "$scene" --project --output-times 0:0.005:10 -o "$work/top.csv" > "$work/top.log"
check "$work/top.csv" "" 0.9999
"$nhc" simulate "$scene" --project --output-times 0:0.005:10 --set s=0 -o "$work/flip.csv" > "$work/flip.log"
check "$work/flip.csv" -0.9999 ""
