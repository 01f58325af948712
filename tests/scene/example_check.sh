#!/bin/sh
# An example scene end to end: nhc derive (text and LaTeX with the multiplier-free form, which must compile with pdflatex when
# it is installed), analyze, generate and simulate, then checks on the simulated CSV.
# Usage: example_check.sh NHC SCENE WORKDIR [simulate-only] CHECK...
#   simulate-only           skip the separate text derive, analyze and generate runs (simulate
#                           derives, analyses and generates itself): for scenes whose symbolic
#                           stage takes tens of seconds (the Whipple bicycle)
#   drift:COLUMN:TOL        |value - first value| <= TOL on every row (a conserved quantity)
#   abs:COLUMN:TOL          |value| <= TOL on every row (a reference error, a hidden constraint)
#   decreasing:COLUMN:TOL   value <= previous value + TOL, and the last value < the first
#   decays:COLUMN:FRACTION  max |value| over the last fifth <= FRACTION * max |value| over the first fifth
#   reverses:COLUMN:FRACTION  the last value has the first's opposite sign and >= FRACTION of its size
# Columns are matched by prefix (hidden: matches every hidden constraint).
set -eu
nhc=$1 scene=$2 work=$3
shift 3
separate_steps=yes
if [ "${1:-}" = simulate-only ]; then separate_steps=no; shift; fi
rm -rf "$work" && mkdir -p "$work"
[ $separate_steps = no ] || "$nhc" derive "$scene" -o "$work/derive.txt"
"$nhc" derive "$scene" --format latex --form reduced -o "$work/derive.tex"
if command -v pdflatex > /dev/null; then
  (cd "$work" && pdflatex -interaction=nonstopmode -halt-on-error derive.tex > latex.log < /dev/null) ||
    { echo "derive --format latex does not compile:"; tail -20 "$work/latex.log"; exit 1; }
fi
if [ $separate_steps = yes ]; then
  "$nhc" analyze "$scene" -o "$work/analysis.txt"
  "$nhc" generate "$scene" -o "$work/generated"
fi
"$nhc" simulate "$scene" -o "$work/run.csv"
for check in "$@"; do
  kind=${check%%:*} rest=${check#*:}
  column=${rest%:*} limit=${rest##*:}  # the column may hold colons (invariant:energy)
  awk -F, -v kind="$kind" -v column="$column" -v limit="$limit" '
    NR == 1 { for (i = 1; i <= NF; ++i) if (index($i, column) == 1) cols[++n] = i
              if (n == 0) { print "no column " column; bad = 1; exit 1 }
              next }
    { rows[NR - 1] = $0; last = NR - 1 }
    END {
      if (bad) exit 1
      for (c = 1; c <= n; ++c) {
        i = cols[c]; worst = 0; early = 0; late = 0
        for (r = 1; r <= last; ++r) {
          split(rows[r], f, ","); v = f[i] + 0
          if (r == 1) first = v
          a = v < 0 ? -v : v
          if (kind == "drift") { d = v - first; d = d < 0 ? -d : d; if (d > worst) worst = d }
          if (kind == "abs" && a > worst) worst = a
          if (kind == "decreasing" && r > 1 && v > previous + limit) { print column " rises at row " r; exit 1 }
          if (kind == "decays") { if (r <= last / 5 && a > early) early = a; if (r > last * 4 / 5 && a > late) late = a }
          previous = v
        }
        if ((kind == "drift" || kind == "abs") && worst > limit) { print kind " " column ": " worst " > " limit; exit 1 }
        if (kind == "decreasing" && !(previous < first)) { print column " does not decrease"; exit 1 }
        if (kind == "decays" && !(late <= limit * early)) { print column ": late " late " vs early " early; exit 1 }
        if (kind == "reverses" && !(previous * first < 0 && (previous < 0 ? -previous : previous) >= limit * (first < 0 ? -first : first))) {
          print column ": first " first ", last " previous; exit 1 }
        printf "%s %s: ok (%g %g %g)\n", kind, column, worst, early, late
      }
    }' "$work/run.csv"
done
