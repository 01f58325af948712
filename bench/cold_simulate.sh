#!/usr/bin/env bash
# Cold `nhc simulate`: empty caches (a fresh NHC_CACHE_DIR, which holds the compile and
# the scene cache), --backend auto, wall and processor time of the whole command (/usr/bin/time),
# best of REPEAT; then the same scene --backend compiled, also from empty caches, and the largest
# relative difference of the two CSVs (|a - b| over the column's largest |b|, the worst column but
# the hidden constraints' drifts, which are zero to rounding; the goal: <= 1e-12). The compiled run
# must be cold too: a run that finds the initial-point check in the scene cache skips the analysis,
# and the header it derives then differs from a cold run's in the order of terms (the analysis
# creates symbols, and GiNaC orders terms by the symbols' serial numbers): the same model to
# rounding, whose 5 s bicycle run differs by 8.5e-12 of the lambda4 column.
# Usage: bench/cold_simulate.sh NHC SCENE...   (prints Markdown on stdout)
set -euo pipefail
nhc=$1
shift
repeat=${NHC_COLD_REPEAT:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
unset NHC_BACKEND
echo "| scene | cold \`nhc simulate\` (auto): wall, best of $repeat | its processor time | how it ran | largest difference to --backend compiled, relative to the column |"
echo "|---|---|---|---|---|"
for scene in "$@"; do
  best_wall=1e300 best_cpu=0 how=""
  for _ in $(seq "$repeat"); do
    rm -rf "$work/cache"
    NHC_CACHE_DIR="$work/cache" /usr/bin/time -f "%e %U %S" -o "$work/time" "$nhc" simulate "$scene" -o "$work/auto.csv" > "$work/out"
    read -r wall user sys < "$work/time"
    if awk -v a="$wall" -v b="$best_wall" 'BEGIN{exit !(a < b)}'; then
      best_wall=$wall best_cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN{printf "%.2f", u + s}')
      how=$(grep -o "interpreted[^,]*\|compile[^,]*" "$work/out" | head -1)
    fi
  done
  rm -rf "$work/cache"
  NHC_CACHE_DIR="$work/cache" "$nhc" simulate "$scene" --backend compiled -o "$work/compiled.csv" > /dev/null
  difference=$(python3 - "$work/auto.csv" "$work/compiled.csv" <<'PY'
import csv, sys
a, b = (list(csv.reader(open(p))) for p in sys.argv[1:3])
if len(a) != len(b) or a[0] != b[0]:
    print("different shapes"); sys.exit()
worst, where = 0.0, ""
for j, name in enumerate(a[0]):
    xs = [float(r[j]) for r in a[1:]]
    ys = [float(r[j]) for r in b[1:]]
    scale = max(abs(y) for y in ys)
    if scale == 0 or name.startswith("hidden:"): continue  # hidden: constraint drifts, zero to rounding
    d = max(abs(x - y) for x, y in zip(xs, ys)) / scale
    if d > worst: worst, where = d, f" ({name})"
print(f"{worst:.2g}{where}")
PY
)
  echo "| $(basename "$scene" .toml) | $best_wall s | $best_cpu s | $how | $difference |"
done
