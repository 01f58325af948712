#!/usr/bin/env python3
"""The Python package's overhead: 1000 runs of Model.simulate on the knife edge from
Python against the same 1000 runs from C++ (bench/python_overhead.cpp: runtime::simulate with the
same options and output times, in a loop). The two sides alternate in blocks, so that a change of
the machine's load hits both alike; each side's loop is timed in its own process. Writes
bench/python-overhead.md (or the file given with --out).

    bench/python_overhead.sh            # configures build-bench, builds, runs this
    PYTHONPATH=build-bench/python python3 bench/python_overhead.py --bench build-bench/bench/nhc_python_overhead
"""
import argparse
import datetime
import json
import os
import pathlib
import platform
import statistics
import subprocess
import time

import nhc

ROOT = pathlib.Path(__file__).resolve().parents[1]
GOAL = 1.2  # the goal: the Python loop costs at most 1.2x the C++ loop


def python_block(model, runs, settings):
    start = time.perf_counter()
    for _ in range(runs):
        model.simulate(**settings)
    return time.perf_counter() - start


def cpp_block(bench, scene, runs, settings):
    out = subprocess.run([bench, str(scene), "--runs", str(runs), "--t-end", str(settings["t_end"]),
                          "--outputs", str(settings["outputs"]), "--rtol", str(settings["rtol"]),
                          "--atol", str(settings["atol"])], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bench", required=True, help="the nhc_python_overhead executable")
    parser.add_argument("--scene", default=str(ROOT / "examples" / "knife_edge.toml"))
    parser.add_argument("--runs", type=int, default=1000, help="runs per side (default 1000)")
    parser.add_argument("--blocks", type=int, default=5, help="alternating blocks (default 5)")
    parser.add_argument("--out", default=str(ROOT / "bench" / "python-overhead.md"))
    args = parser.parse_args()
    settings = dict(t_end=1.0, rtol=1e-8, atol=1e-10, outputs=200)
    scene = nhc.Scene.load(args.scene)
    model = scene.build(scene.models[0] if "chetaev" not in scene.models else "chetaev")
    per_block = max(1, args.runs // args.blocks)
    model.simulate(**settings)  # warm: the model's first call
    py, cpp, cpp_rows = [], [], []
    steps = states = None
    for block in range(args.blocks):
        measured = cpp_block(args.bench, args.scene, per_block, settings)
        cpp.append(measured["simulate"])
        cpp_rows.append(measured["simulate_rows_drift"])
        steps, states = measured["steps"], measured["states"]
        py.append(python_block(model, per_block, settings))
        print(f"block {block + 1}/{args.blocks}: C++ {cpp[-1]:.3f} s (with rows and drift {cpp_rows[-1]:.3f} s), "
              f"Python {py[-1]:.3f} s", flush=True)
    runs = per_block * args.blocks
    ratio = sum(py) / sum(cpp)
    ratio_rows = sum(py) / sum(cpp_rows)
    block_ratios = [p / c for p, c in zip(py, cpp)]
    run = model.simulate(**settings)
    verdict = "met" if ratio <= GOAL else "not met"
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip() or "unknown"
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    text = f"""# The Python package's overhead

Measured by `bench/python_overhead.sh` (bench/python_overhead.py and bench/python_overhead.cpp) on
{datetime.date.today().isoformat()}, commit {commit}, {platform.processor() or platform.machine()}, {os.cpu_count()} cores,
load average {load:.2f} at the end; Python {platform.python_version()}.

{runs} runs of the knife edge (`{pathlib.Path(args.scene).relative_to(ROOT) if pathlib.Path(args.scene).is_relative_to(ROOT) else args.scene}`,
chetaev, {states} states, {steps} steps per run; t_end {settings['t_end']}, rtol {settings['rtol']}, atol
{settings['atol']}, {settings['outputs']} outputs) from Python, `model.simulate(...)` in a loop (each call
returns a `Run`: the CSV's {len(run.columns)} columns as a numpy matrix and the summary with the
drift), against the same runs from C++: `runtime::simulate` with the same options and output times
in a loop. The sides alternate in {args.blocks} blocks of {per_block} runs; each loop is timed in its own
process (the model built beforehand, from the compile cache).

| side | {runs} runs | per run |
|---|---|---|
| C++, `runtime::simulate` | {sum(cpp):.3f} s | {1e3 * sum(cpp) / runs:.3f} ms |
| C++, `runtime::simulate` + the rows as a matrix + `measure_drift` (what a Run holds) | {sum(cpp_rows):.3f} s | {1e3 * sum(cpp_rows) / runs:.3f} ms |
| Python, `model.simulate` | {sum(py):.3f} s | {1e3 * sum(py) / runs:.3f} ms |

**Python / C++ = {ratio:.3f}** (goal at most {GOAL}: **{verdict}**); per block
{', '.join(f'{r:.3f}' for r in block_ratios)} (median {statistics.median(block_ratios):.3f}). Against the
C++ loop that also builds what a Run holds: {ratio_rows:.3f}.
"""
    pathlib.Path(args.out).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
