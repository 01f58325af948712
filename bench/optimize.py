#!/usr/bin/env python3
"""nhc optimize with generated derivatives against IPOPT's approximations.

Runs `nhc optimize` on the car parking and the wheeled pendulum (the issue's two problems with
[inputs]) and on the Heisenberg loop (no inputs, closed-form cost pi), each in three set-ups:
  exact / exact                 the generated Jacobian and Hessian (the default)
  exact / limited-memory        the generated Jacobian, IPOPT's quasi-Newton Hessian
  finite-differences / exact    IPOPT's differences of the constraints (one variable at a time,
                                on the same sparsity), the generated Hessian
  finite-differences / l-m      the differences and the quasi-Newton Hessian: no generated
                                derivative beyond the objective's gradient
recording the exit code, IPOPT's iterations, the best wall time and the processor time (of the
process, user + system) over --repeats processes, and writes bench/optimize.md.

Usage: bench/optimize.py NHC [--repeats 1] [--timeout 900] [--out bench/optimize.md]
"""
import argparse
import os
import re
import resource
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROBLEMS = [
    ("car parking", "examples/car_parking.toml"),
    ("wheeled pendulum", "examples/wheeled_pendulum_move.toml"),
    ("Heisenberg loop", "examples/heisenberg_optimal.toml"),
]
SETUPS = [("exact", "exact"), ("exact", "limited-memory"), ("finite-differences", "exact"),
          ("finite-differences", "limited-memory")]


def run(nhc, scene, jacobian, hessian, timeout):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    try:
        done = subprocess.run([nhc, "optimize", os.path.join(ROOT, scene), "--jacobian", jacobian, "--hessian", hessian],
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "wall": float("nan"), "cpu": float("nan"), "cost": float("nan"),
                "iterations": None, "words": f"no answer in {timeout:g} s (stopped)"}
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    cost = re.search(r"cost = (\S+)", done.stdout)
    iterations = len(re.findall(r"^  iteration ", done.stderr, re.M)) - 1  # IPOPT counts from 0
    return {
        "status": done.returncode,
        "wall": wall,
        "cpu": cpu,
        "cost": float(cost.group(1)) if cost else float("nan"),
        "iterations": iterations,
        "words": done.stderr.strip().splitlines()[-1] if done.returncode else "",
    }


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("nhc")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--out", default=os.path.join(ROOT, "bench", "optimize.md"))
    parser.add_argument("--timeout", type=float, default=900, help="seconds a run may take before it is stopped")
    args = parser.parse_args()
    rows = []
    load = os.getloadavg()[0]
    # The set-ups in turn over the problems, the slow approximations last; the report is written
    # again after each row, so that a run cut short still leaves one.
    for jacobian, hessian in SETUPS:
        for name, scene in PROBLEMS:
            runs = [run(args.nhc, scene, jacobian, hessian, args.timeout) for _ in range(args.repeats)]
            best = min(runs, key=lambda r: r["wall"] if r["wall"] == r["wall"] else float("inf"))
            best["cpu"] = min(r["cpu"] for r in runs)
            rows.append((name, scene, jacobian, hessian, best))
            print(name, jacobian, hessian, best, flush=True)
            load = max(load, os.getloadavg()[0])
            write(args, rows, load)
    print("wrote", args.out)


def write(args, rows, load):
    rows = sorted(rows, key=lambda r: ([p for p, _ in PROBLEMS].index(r[0]), SETUPS.index((r[2], r[3]))))
    with open(args.out, "w") as out:
        out.write("# nhc optimize: generated derivatives against IPOPT's approximations\n\n")
        out.write(f"`bench/optimize.py` with each scene's own [optimize] settings; the best wall time and the least "
                  f"processor time (user + system) of {args.repeats} processes each, the whole command (reading, "
                  "deriving, solving). Jacobian `exact`: the constraints' derivatives generated from the scene "
                  "(docs/optimize.md); `finite-differences`: IPOPT's `jacobian_approximation = "
                  "finite-difference-values` on the same sparsity. Hessian `exact`: the generated second "
                  "derivatives; `limited-memory`: IPOPT's quasi-Newton approximation (L-BFGS).")
        out.write(f" The machine is shared (2 cores, several people building; load average up to {load:.1f} "
                  "during the run): wall times measure the machine as much as nhc, processor times less so, "
                  "and the iterations and costs not at all.\n\n")
        out.write("| problem | Jacobian | Hessian | exit | IPOPT iterations | wall time (s) | processor time (s) | cost |\n"
                  "|---|---|---|---|---|---|---|---|\n")
        for name, scene, jacobian, hessian, r in rows:
            out.write(f"| {name} | {jacobian} | {hessian} | {r['status']} | "
                      f"{r['iterations'] if r['iterations'] is not None else '-'} | {r['wall']:.2f} | {r['cpu']:.2f} | "
                      f"{r['cost']:.10g} |\n")
        out.write(f"\nA run past {args.timeout:g} s is stopped (exit `timeout`).\n")
        failed = [(name, j, h, r["words"]) for name, _, j, h, r in rows if r["status"]]
        if failed:
            out.write("\nNot optimal:\n\n")
            for name, j, h, words in failed:
                out.write(f"- {name}, {j} / {h}: {words}\n")


if __name__ == "__main__":
    main()
