#!/usr/bin/env bash
# Scene-language details, each against an independent path:
#  1. [reference.MODEL]: the Heisenberg system's chetaev line and vakonomic arc (closed forms in
#     tests/scene/scenes/heisenberg_two_models.toml) are each met by their own model's run, where
#     one plain [reference] table leaves the vakonomic run far from it;
#  2. [invariants] with multipliers: lambda1 is an invariant of both models (0 and 2), lambda1' is
#     computed by the vakonomic model only and left out of the chetaev CSV with a note;
#  3. a relative equilibrium (the rolling disk spinning in place about its vertical diameter) is
#     refused in words naming the coordinate that moves; written in the frame turned by the
#     heading (docs/linearize.md, "Relative equilibria") it linearizes, and its lean frequency
#     matches the one a simulation of the original coordinates shows.
# Usage: scene_details_test.sh NHC SOURCE_DIR WORKDIR
set -euo pipefail
nhc=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
reference_error() { sed -n 's/^  max reference error \([^ ]*\)$/\1/p' "$1"; }
below() { python3 -c "import sys; sys.exit(0 if float('$1') < float('$2') else 1)"; }

# 1. and 2.
scene=$src/tests/scene/scenes/heisenberg_two_models.toml
for model in chetaev vakonomic; do
  "$nhc" simulate "$scene" -m "$model" -o "$work/$model.csv" > "$work/$model.out" 2> "$work/$model.err" ||
    fail "simulate -m $model: $(cat "$work/$model.err")"
  e=$(reference_error "$work/$model.out")
  [ -n "$e" ] || fail "$model: no reference error in $(cat "$work/$model.out")"
  below "$e" 1e-7 || fail "$model: reference error $e against its own closed form"
done
head -1 "$work/chetaev.csv" | grep -q 'invariant:multiplier,' || head -1 "$work/chetaev.csv" | grep -q 'invariant:multiplier$' ||
  fail "chetaev CSV lacks invariant:multiplier: $(head -1 "$work/chetaev.csv")"
head -1 "$work/chetaev.csv" | grep -q 'multiplier_rate' && fail "chetaev CSV has multiplier_rate"
grep -q "^note: invariant 'multiplier_rate' is left out of the chetaev model's CSV: it uses lambda1'" "$work/chetaev.err" ||
  fail "no note on multiplier_rate: $(cat "$work/chetaev.err")"
head -1 "$work/vakonomic.csv" | grep -q 'invariant:multiplier_rate' || fail "vakonomic CSV lacks multiplier_rate"
# The plain table alone: the vakonomic run is judged against the chetaev line (the old behaviour).
sed '/^\[reference.vakonomic\]/,/^$/d' "$scene" > "$work/plain_reference.toml"
"$nhc" simulate "$work/plain_reference.toml" -m vakonomic -o "$work/plain.csv" > "$work/plain.out" 2>&1
e=$(reference_error "$work/plain.out")
below 0.1 "$e" || fail "without [reference.vakonomic] the error should be large, got $e"

# 3.
disk=$src/tests/linearize/scenes/rolling_disk.toml
set +e
"$nhc" linearize "$disk" --at "ph'=4" --at "ps'=0" > "$work/lin.out" 2> "$work/lin.err"
rc=$?
set -e
[ $rc -eq 3 ] || fail "linearize of a relative equilibrium: exit $rc, want 3"
grep -q "ph moves but is not cyclic (it appears in R_x" "$work/lin.err" || fail "message: $(cat "$work/lin.err")"
grep -q 'Relative equilibria' "$work/lin.err" || fail "message without the docs pointer: $(cat "$work/lin.err")"
[ "$(wc -l < "$work/lin.err")" -eq 1 ] || fail "message is not one line"

"$nhc" linearize "$src/tests/linearize/scenes/rolling_disk_turning_frame.toml" --format json > "$work/turning.json"
# The same motion (th = 0, ph' = 4, ps' = 0), started with a lean rate of 1e-4 in the original
# coordinates x, y, and integrated for three lean periods.
sed -e 's/^th = \[0.0, 0.0\]/th = [0.0, 0.0001]/' -e 's/^ph = \[0.0, 0.0\]/ph = [0.0, 4.0]/' \
    -e 's/^ps = \[0.0, 6.0\]/ps = [0.0, 0.0]/' "$disk" > "$work/spinning.toml"
"$nhc" simulate "$work/spinning.toml" --t-end 36 --outputs 7200 --rtol 1e-11 --atol 1e-14 -o "$work/spinning.csv" > /dev/null
python3 - "$work/turning.json" "$work/spinning.csv" <<'PY'
import csv, json, math, sys
lin = json.load(open(sys.argv[1]))
assert lin["defect"] < 1e-12, lin["defect"]
assert "ph" in lin["cyclic"], lin["cyclic"]
# The lean mode: the imaginary pair that is not the frame's rotation at ph' = 4.
lean = sorted(abs(e["im"]) for e in lin["eigenvalues"] if 0.01 < abs(e["im"]) < 3.9)
assert len(lean) == 2 and all(abs(e["re"]) < 1e-12 for e in lin["eigenvalues"]), lin["eigenvalues"]
rows = list(csv.DictReader(open(sys.argv[2])))
t = [float(r["t"]) for r in rows]
th = [float(r["th"]) for r in rows]
# Maxima of th, each placed by the parabola through the three samples around it.
peaks = []
for i in range(1, len(t) - 1):
    if th[i] > th[i - 1] and th[i] >= th[i + 1]:
        h = t[i + 1] - t[i]
        a, b, c = th[i - 1], th[i], th[i + 1]
        peaks.append(t[i] + h * (a - c) / (2 * (a - 2 * b + c)))
assert len(peaks) >= 3, peaks
omega = 2 * math.pi * (len(peaks) - 1) / (peaks[-1] - peaks[0])
print(f"lean frequency: linearized {lean[0]:.9f}, simulated {omega:.9f}")
assert abs(omega - lean[0]) < 1e-4 * lean[0], (omega, lean[0])
PY
echo "scene details: all checks passed"
