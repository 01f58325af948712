#!/usr/bin/env bash
# The Python package's overhead benchmark: configures build-bench with the benchmark
# drivers, builds the Python module and nhc_python_overhead, and runs bench/python_overhead.py,
# which writes bench/python-overhead.md. Arguments are passed on (--runs, --blocks, --out).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${NHC_BENCH_BUILD_DIR:-build-bench}
python=${PYTHON:-/usr/bin/python3}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DNHC_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j"$(nproc)" --target nhc nhc_python nhc_python_overhead >/dev/null
PYTHONPATH="$build/python" "$python" bench/python_overhead.py --bench "$build/bench/nhc_python_overhead" "$@"
