#!/usr/bin/env python3
"""nhc optimize with exact constraint Jacobians against IPOPT's finite differences (issue 49).

Runs `nhc optimize examples/heisenberg_optimal.toml` at several interval counts, once with the
exact Jacobian (the default) and once with `--jacobian finite-differences` (IPOPT differencing the
constraints on the same sparsity), each the best wall time of --repeats processes, and writes
bench/optimize.md with the iterations, the wall time and the cost's error against 2 pi a / T.

Usage: bench/optimize.py NHC [--intervals 40,80,160,320] [--repeats 3] [--out bench/optimize.md]
"""
import argparse
import math
import os
import re
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "examples", "heisenberg_optimal.toml")
EXACT_COST = 2 * math.pi * 0.5 / 1.0  # a = 0.5, T = 1 in the scene


def run(nhc, intervals, jacobian):
    start = time.perf_counter()
    done = subprocess.run([nhc, "optimize", SCENE, "--intervals", str(intervals), "--jacobian", jacobian],
                          capture_output=True, text=True, timeout=600)
    wall = time.perf_counter() - start
    cost = re.search(r"cost = (\S+)", done.stdout)
    iterations = re.search(r"iterations = (\d+)", done.stdout)
    return {
        "status": done.returncode,
        "wall": wall,
        "cost": float(cost.group(1)) if cost else float("nan"),
        "iterations": int(iterations.group(1)) if iterations else None,
        "words": done.stderr.strip().splitlines()[-1] if done.returncode else "",
    }


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("nhc")
    parser.add_argument("--intervals", default="40,80,160,320")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--out", default=os.path.join(ROOT, "bench", "optimize.md"))
    args = parser.parse_args()
    rows = []
    for n in [int(v) for v in args.intervals.split(",")]:
        for jacobian in ("exact", "finite-differences"):
            runs = [run(args.nhc, n, jacobian) for _ in range(args.repeats)]
            best = min(runs, key=lambda r: r["wall"])
            rows.append((n, jacobian, best))
            print(n, jacobian, best, flush=True)
    load = os.getloadavg()[0]
    with open(args.out, "w") as out:
        out.write("# nhc optimize: exact Jacobians against finite differences\n\n")
        out.write("`bench/optimize.py` on `examples/heisenberg_optimal.toml` (a = 0.5, T = 1: cost pi), "
                  f"best wall time of {args.repeats} processes each (load {load:.2f} at the end). `exact`: the "
                  "constraint Jacobian from the symbolic derivatives (docs/optimize.md); `finite-differences`: "
                  "IPOPT's `jacobian_approximation = finite-difference-values` on the same sparsity. "
                  "Both with limited-memory Hessians.")
        if load > (os.cpu_count() or 1):
            out.write(f" The machine was loaded (load {load:.2f} on {os.cpu_count()} cores): the wall times "
                      "measure the machine as much as nhc; the iterations and errors do not depend on it.")
        out.write("\n\n")
        out.write("| intervals | Jacobian | exit | IPOPT iterations | wall time (s) | cost error |\n|---|---|---|---|---|---|\n")
        for n, jacobian, r in rows:
            error = abs(r["cost"] - EXACT_COST)
            out.write(f"| {n} | {jacobian} | {r['status']} | {r['iterations'] if r['iterations'] is not None else '-'} | "
                      f"{r['wall']:.3f} | {error:.2e} |\n")
        failed = [(n, j, r["words"]) for n, j, r in rows if r["status"]]
        if failed:
            out.write("\nFailures:\n\n")
            for n, j, words in failed:
                out.write(f"- {n} intervals, {j}: {words}\n")
    print("wrote", args.out)


if __name__ == "__main__":
    main()
