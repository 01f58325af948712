#!/usr/bin/env bash
# The second run of a scene (docs/interpreter.md, "The second run"): `nhc simulate` with the
# default backend (auto) from an empty cache (cold), then runs 2 … 10 on the same cache, each
# alternating with a run of the compiled model from a cache where it was compiled before
# (--backend compiled, its own NHC_CACHE_DIR); the whole series REPEAT times, each from an empty
# cache. Wall time of the whole command (/usr/bin/time); cold, second and tenth: the minimum over
# the series; compiled: the minimum over all its runs. The CSVs of every auto run are compared
# with the compiled run's byte for byte; the cache's size on disk after ten runs (du).
# Usage: bench/second_run.sh NHC SCENE...   (prints Markdown on stdout; NHC_SECOND_REPEAT, default 3)
set -euo pipefail
nhc=$1
shift
repeat=${NHC_SECOND_REPEAT:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
unset NHC_BACKEND NHC_CACHE_DIR
wall() {  # wall CACHE OUT ARGS…: runs nhc, prints its wall seconds; its stdout in $work/out
  local cache=$1 out=$2; shift 2
  NHC_CACHE_DIR=$cache /usr/bin/time -f "%e" -o "$work/time" "$nhc" simulate "$@" -o "$out" >"$work/out"
  cat "$work/time"
}
min() { printf '%s\n' "$@" | sort -g | head -1; }
echo "Load average at the start: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores; repeat $repeat."
echo
echo "| scene | cold (auto) | second | tenth | compiled, cached | second / compiled | tenth / compiled | how the second ran | CSV = compiled's | cache after ten runs (scenes/ of it) |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for scene in "$@"; do
  name=$(basename "$scene" .toml)
  compiled_cache=$work/compiled-$name
  wall "$compiled_cache" "$work/compiled.csv" "$scene" --backend compiled >/dev/null
  cold=() second=() tenth=() compiled=() same=yes how=""
  for r in $(seq "$repeat"); do
    cache=$work/auto-$name
    rm -rf "$cache"
    cold+=("$(wall "$cache" "$work/auto.csv" "$scene")")
    cmp -s "$work/auto.csv" "$work/compiled.csv" || same=no
    for k in $(seq 2 10); do
      compiled+=("$(wall "$compiled_cache" "$work/compiled.csv" "$scene" --backend compiled)")
      t=$(wall "$cache" "$work/auto.csv" "$scene")
      cmp -s "$work/auto.csv" "$work/compiled.csv" || same=no
      [ "$k" -eq 2 ] && second+=("$t") && how=$(grep -o "time: .*" "$work/out" | sed 's/, integrate.*//')
      [ "$k" -eq 10 ] && tenth+=("$t")
    done
  done
  c=$(min "${cold[@]}") s=$(min "${second[@]}") t=$(min "${tenth[@]}") k=$(min "${compiled[@]}")
  size=$(du -sh "$cache" | cut -f1) scenes=$(du -sh "$cache/scenes" | cut -f1)
  ratio() { awk -v a="$1" -v b="$2" 'BEGIN{printf "%.2f", a / b}'; }
  echo "| $name | $c s | $s s | $t s | $k s | $(ratio "$s" "$k") | $(ratio "$t" "$k") | $how | $same | $size ($scenes) |"
  rm -rf "$cache" "$compiled_cache"
done
echo
echo "Load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)."
