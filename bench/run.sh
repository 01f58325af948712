#!/usr/bin/env bash
# The benchmark suite: nhc on the knife-edge chain (bench/knife_chain.py) and on
# the paper's two examples, side by side with SymPy (LagrangesMethod, cse, lambdify), SciPy
# (solve_ivp Radau/BDF) and hand-written residuals and Jacobians; the front end's scaling to
# N = 1024 (bench/frontend_scaling.py, cold: scene cache off), the scene-cache warm `nhc simulate`,
# the second family (bench/particle_chain.py, second-order constraints; the vakonomic knife
# chain) and the rigid bodies (bench/rolling_balls.py, N rolling balls written with
# definitions; with the Whipple bicycle beside SymPy, bench/whipple_sympy.py). Writes bench/results.md (with the front end's goal table, met / not met) and
# bench/results-time.svg; everything in them is measured in this run.
#
#   bench/run.sh            # the full run (hours while the front end is slow at N = 1024)
#   bench/run.sh --quick    # small N sets, peers at N = 1 and 2 only (CI; under 2 minutes); writes
#                           # results.md and results-time.svg into $NHC_BENCH_BUILD_DIR/bench-out/
#                           # instead of bench/ (bench/results.md holds a full run)
# As root on a fresh Debian machine it installs what is missing.
# Environment (defaults full / --quick): NHC_BENCH_BUILD_DIR (build-bench),
# NHC_BENCH_N compile+run with the hand-written limit ("1 2 4 8 16 32 64" / "1 4 16 64"),
# NHC_BENCH_PEER_N ("1 2 4 8 16" / "1 2"), NHC_BENCH_PEER_TIMEOUT (seconds per peer run, 600),
# NHC_BENCH_FRONTEND_N ("16 32 64 128 256 512 1024" / "16 32 64 128 256"),
# NHC_BENCH_FAMILY2_N ("1 2 4 8 16 32 64 128 256" / "1 4 16 64"),
# NHC_BENCH_RIGID_N ("1 2 4 8 16 32 64 128" / "1 4 16"; cold simulate up to 16 / 4),
# NHC_BENCH_WARM_N (512 / 64), NHC_BENCH_STAGE_TIMEOUT (seconds per nhc command, 900 / 60),
# PYTHON (default /usr/bin/python3, the interpreter Debian's python3-sympy/-scipy belong to).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s.%N)
quick=0
case "${1:-}" in
  --quick) quick=1 ;;
  "") ;;
  *) echo "bench/run.sh: unknown option $1 (usage: bench/run.sh [--quick])" >&2; exit 2 ;;
esac
build=${NHC_BENCH_BUILD_DIR:-build-bench}
if [ $quick = 1 ]; then
  nhc_n=${NHC_BENCH_N:-"1 4 16 64"}
  peer_n=${NHC_BENCH_PEER_N:-"1 2"}
  frontend_n=${NHC_BENCH_FRONTEND_N:-"16 32 64 128 256"}
  family2_n=${NHC_BENCH_FAMILY2_N:-"1 4 16 64"}
  rigid_n=${NHC_BENCH_RIGID_N:-"1 4 16"}
  rigid_simulate_n=4
  warm_n=${NHC_BENCH_WARM_N:-64}
  stage_timeout=${NHC_BENCH_STAGE_TIMEOUT:-60}
  absurd_count=${NHC_BENCH_ABSURD_COUNT:-6}
  bench_quick=(--quick)
else
  nhc_n=${NHC_BENCH_N:-"1 2 4 8 16 32 64"}
  peer_n=${NHC_BENCH_PEER_N:-"1 2 4 8 16"}
  frontend_n=${NHC_BENCH_FRONTEND_N:-"16 32 64 128 256 512 1024"}
  family2_n=${NHC_BENCH_FAMILY2_N:-"1 2 4 8 16 32 64 128 256"}
  rigid_n=${NHC_BENCH_RIGID_N:-"1 2 4 8 16 32 64 128"}
  rigid_simulate_n=16
  warm_n=${NHC_BENCH_WARM_N:-512}
  stage_timeout=${NHC_BENCH_STAGE_TIMEOUT:-900}
  absurd_count=${NHC_BENCH_ABSURD_COUNT:-200}
  bench_quick=()
fi
peer_timeout=${NHC_BENCH_PEER_TIMEOUT:-600}
# The suite times the compiled pipeline (derive, compile, run); the interpreter has its own entry
# (bench/interpreter.cpp). NHC_BACKEND=auto would run short scenes interpreted.
export NHC_BACKEND=${NHC_BACKEND:-compiled}
python=${PYTHON:-/usr/bin/python3}
log() { echo "bench: $*" >&2; }

# --- what the peers and the plot need ---
missing=()
"$python" -c 'import sympy' 2>/dev/null || missing+=(python3-sympy)
"$python" -c 'import scipy, numpy' 2>/dev/null || missing+=(python3-scipy python3-numpy)
command -v gnuplot >/dev/null || missing+=(gnuplot-nox)
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "bench/run.sh: missing ${missing[*]}; install them (apt-get install ${missing[*]}) or run as root" >&2
    exit 2
  fi
  log "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get install -y --no-install-recommends "${missing[@]}" >/dev/null ||
    { apt-get update >/dev/null && apt-get install -y --no-install-recommends "${missing[@]}" >/dev/null; }
fi
[ -x "$python" ] || python=python3

# --- build the driver (the library, the runtime and bench/; not the test suite) ---
log "building nhc_bench in $build"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DNHC_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j"$(nproc)" --target nhc nhc_bench >/dev/null
bench="$build/bench/nhc_bench"
nhc="$build/cli/nhc"
out="$build/bench-out"
json="$out/json"
rm -rf "$out"
mkdir -p "$json" "$out/scenes"
if [ $quick = 1 ]; then results="$out"; else results=bench; fi
load_start=$(cut -d' ' -f1-3 /proc/loadavg)

# --- nhc (and the hand-written limit) ---
# shellcheck disable=SC2086
"$python" bench/knife_chain.py "$out/scenes" $nhc_n $family2_n
# Compile + run (nhc_bench) stops at the largest NHC_BENCH_N; each run is limited like a stage.
for n in $nhc_n; do
  log "nhc, knife chain N = $n"
  timeout -k 10 "$stage_timeout" "$bench" "$out/scenes/knife_chain_$n.toml" --out "$out/nhc/$n" "${bench_quick[@]}" \
    --handwritten bench/knife_chain_handwritten.hpp --define "NHC_BENCH_CHAIN_N=$n" \
    >"$json/nhc_knife_chain_$n.json" || { log "nhc_bench failed at N = $n"; rm -f "$json/nhc_knife_chain_$n.json"; }
done
log "nhc, appell_hamel"
timeout -k 10 "$stage_timeout" "$bench" examples/appell_hamel.toml --out "$out/nhc/appell_hamel" "${bench_quick[@]}" \
  --handwritten tests/runtime/handwritten/appell_hamel_chetaev.hpp >"$json/nhc_appell_hamel.json" ||
  { log "nhc_bench failed on appell_hamel"; rm -f "$json/nhc_appell_hamel.json"; }
log "nhc, particle"
timeout -k 10 "$stage_timeout" "$bench" examples/particle.toml --out "$out/nhc/particle" "${bench_quick[@]}" >"$json/nhc_particle.json" ||
  { log "nhc_bench failed on particle"; rm -f "$json/nhc_particle.json"; }

# --- the front end's scaling, cold (scene cache off), and the scene-cache warm simulate ---
log "front end, knife chain (chetaev), N = $frontend_n; warm simulate at N = $warm_n"
# shellcheck disable=SC2086
"$python" bench/frontend_scaling.py "$nhc" "$json/frontend_knife_chain_chetaev.json" --family knife_chain \
  --model chetaev --timeout "$stage_timeout" --warm "$warm_n" --warm-timeout "$((2 * stage_timeout))" $frontend_n ||
  log "frontend_scaling.py failed (knife chain)"
# --- rigid bodies: N rolling balls, front end and cold simulate ---
log "front end, rolling balls (chetaev), N = $rigid_n"
# shellcheck disable=SC2086
"$python" bench/frontend_scaling.py "$nhc" "$json/frontend_rolling_balls_chetaev.json" --family rolling_balls \
  --model chetaev --timeout "$stage_timeout" --simulate-up-to "$rigid_simulate_n" $rigid_n ||
  log "frontend_scaling.py failed (rolling balls)"
# --- the second family: second-order constraints (particle chain), the vakonomic knife chain ---
for case in "particle_chain chetaev" "knife_chain vakonomic"; do
  set -- $case
  log "front end, $1 ($2), N = $family2_n"
  # shellcheck disable=SC2086
  "$python" bench/frontend_scaling.py "$nhc" "$json/frontend_$1_$2.json" --family "$1" --model "$2" \
    --timeout "$stage_timeout" $family2_n || log "frontend_scaling.py failed ($1, $2)"
done
# A failed or timed-out nhc_bench run leaves BASE.status (read by bench/report.py) instead of its JSON.
failed() {
  local why
  if [ "$1" = 124 ] || [ "$1" = 137 ]; then why="timed out after $stage_timeout s"
  else why="failed (exit $1): $(grep -v '^$' "$2.err" | tail -1 | cut -c1-200)"; fi
  log "nhc_bench on $3: $why"
  rm -f "$2.json"
  echo "$why" >"$2.status"
}
# shellcheck disable=SC2086
"$python" bench/particle_chain.py "$out/scenes" $family2_n
for n in $family2_n; do
  log "nhc, particle chain N = $n (compile + run)"
  timeout -k 10 "$stage_timeout" "$bench" "$out/scenes/particle_chain_$n.toml" --out "$out/nhc/particle_chain_$n" \
    "${bench_quick[@]}" >"$json/nhc_particle_chain_$n.json" 2>"$json/nhc_particle_chain_$n.err" ||
    failed "$?" "$json/nhc_particle_chain_$n" "the particle chain at N = $n"
done
for n in $family2_n; do
  log "nhc, knife chain vakonomic N = $n (compile + run)"
  timeout -k 10 "$stage_timeout" "$bench" "$out/scenes/knife_chain_$n.toml" --model vakonomic \
    --out "$out/nhc/vakonomic_$n" "${bench_quick[@]}" >"$json/nhc_knife_chain_vakonomic_$n.json" \
    2>"$json/nhc_knife_chain_vakonomic_$n.err" ||
    failed "$?" "$json/nhc_knife_chain_vakonomic_$n" "the vakonomic knife chain at N = $n"
done

# --- SymPy and SciPy ---
for n in $peer_n appell_hamel; do
  log "SymPy/SciPy, $n"
  timeout "$peer_timeout" "$python" bench/peers.py "$n" >"$json/peers_$n.json" ||
    { log "peers.py failed or timed out at $n"; rm -f "$json/peers_$n.json"; }
done

# --- the Whipple bicycle beside SymPy's Kane's method (full runs only: SymPy takes seconds) ---
if [ $quick = 0 ]; then
  log "Whipple bicycle"
  timeout "$peer_timeout" "$python" bench/whipple_sympy.py "$nhc" --markdown="$json/whipple.md" >"$json/whipple.log" 2>&1 ||
    { log "whipple_sympy.py failed or timed out"; rm -f "$json/whipple.md"; }
fi

# --- report and plot ---
cxx=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt")
env_json() {
  NHC_N="$nhc_n" PEER_N="$peer_n" FAMILY2_N="$family2_n" QUICK="$quick" STAGE_TIMEOUT="$stage_timeout" LOAD_START="$load_start" START="$start" \
  CXX_VERSION="$("${cxx:-c++}" --version | head -1)" "$python" - "$json/env.json" <<'PY'
import json, os, sys, time
sys.path.insert(0, "bench")
import knife_chain
import numpy, scipy, sympy
cpu = "?"
try:
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
except OSError:
    pass
with open("/proc/loadavg") as f:
    load_end = " ".join(f.read().split()[:3])
env = {
    "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
    "cpu": cpu, "cores": os.cpu_count(),
    "load_start": os.environ["LOAD_START"], "load_end": load_end,
    "compiler": os.environ["CXX_VERSION"],
    "sympy": sympy.__version__, "scipy": scipy.__version__, "numpy": numpy.__version__,
    "nhc_N": [int(n) for n in os.environ["NHC_N"].split()],
    "peer_N": [int(n) for n in os.environ["PEER_N"].split()],
    "family2_N": [int(n) for n in os.environ["FAMILY2_N"].split()],
    "quick": os.environ["QUICK"] == "1", "stage_timeout_s": float(os.environ["STAGE_TIMEOUT"]),
    "t_end": knife_chain.T_END, "rtol": knife_chain.RTOL, "atol": knife_chain.ATOL,
    "wall_s": time.time() - float(os.environ["START"]),
}
with open(sys.argv[1], "w") as f:
    json.dump(env, f, indent=1)
PY
}
env_json
"$python" bench/report.py "$json" "$results/results.md" "$json/plot.dat"
gnuplot -e "data='$json/plot.dat'; set terminal svg size 900,540 dynamic font 'sans,12'; set output '$results/results-time.svg'" bench/plot.gp
gnuplot -e "data='$json/plot.dat'; set terminal dumb size 110,36; set output '$json/plot.txt'" bench/plot.gp 2>/dev/null
env_json
"$python" bench/report.py "$json" "$results/results.md" "$json/plot.dat"
# No scene may hang nhc: a seeded family of 200 absurd scenes (bench/absurd_scenes.py; 6 with --quick, which only
# keeps the harness running in CI); every one must end with exit 0, 2 or 3 within 5 s under derive,
# derive --format latex and generate. Its table is appended.
absurd_status=0
NHC_SCENE_CACHE=off NHC_CACHE_DIR="$json/absurd-cache" "$python" bench/absurd_scenes.py "$nhc" --count "$absurd_count" \
  --markdown "$json/absurd.md" > "$json/absurd.log" 2>&1 || absurd_status=$?
{
  echo
  echo "## Absurd scenes: $absurd_count seeded Lagrangians under 200 characters, exit 0, 2 or 3 within 5 s"
  echo
  cat "$json/absurd.md" 2>/dev/null || echo "(bench/absurd_scenes.py failed: see $json/absurd.log)"
  if [ "$absurd_status" != 0 ]; then
    echo
    echo "Not met: $(grep -c '^FAIL' "$json/absurd.log") runs past 5 s or with another exit code ($json/absurd.log)."
  fi
} >> "$results/results.md"
# The start-up of the command (perf stat; the libraries each program loads).
if command -v perf > /dev/null; then
  { echo; echo "## Start-up of the command (bench/startup.sh)"; echo
    NHC_STARTUP_REPEAT=$([ $quick = 1 ] && echo 5 || echo 30) bench/startup.sh "$nhc" || echo "(bench/startup.sh failed)"
  } >> "$results/results.md"
fi
# Cold `nhc simulate` (empty caches, --backend auto) of the bicycle, the rattleback and
# the knife chain N = 512, and their results against --backend compiled (bench/cold_simulate.sh).
"$python" bench/knife_chain.py "$out/scenes" 512 > /dev/null
{ echo; echo "## Cold nhc simulate (bench/cold_simulate.sh)"; echo
  bench/cold_simulate.sh "$nhc" examples/whipple/whipple_bicycle.toml examples/rattleback.toml \
    "$out/scenes/knife_chain_512.toml" || echo "(bench/cold_simulate.sh failed)"
} >> "$results/results.md"
# nhc optimize on the car parking, the wheeled pendulum and the Heisenberg loop with the
# generated derivatives against IPOPT's approximations (bench/optimize.py, which also writes
# bench/optimize.md). Not with --quick: the approximations take minutes. Its table is appended.
if [ "$quick" = 0 ]; then
  "$python" bench/optimize.py "$nhc" --out "$json/optimize.md" > "$json/optimize.log" 2>&1 || true
  {
    echo
    echo "## nhc optimize: generated derivatives against IPOPT's approximations"
    echo
    tail -n +3 "$json/optimize.md" 2>/dev/null || echo "(bench/optimize.py failed: see $json/optimize.log)"
  } >> "$results/results.md"
fi
log "wrote $results/results.md and $results/results-time.svg ($(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN{printf "%.0f", e-s}') s)"
