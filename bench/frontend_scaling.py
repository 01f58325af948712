#!/usr/bin/env python3
"""Scaling of nhc's symbolic front end (issue 17) on the knife-edge chain (bench/knife_chain.py).

For each N: wall seconds and peak memory of `nhc derive`, `nhc analyze` and `nhc generate`
(Chetaev), the log-log slope of their sum between the smallest and largest N, and the goal
table (slope <= 1.1, largest N under 10 s and 500 MB). Everything printed is measured in this run.

Usage: frontend_scaling.py NHC OUT.md [--quick] [N ...]
  default N: 32 64 128 192 (the scene reader accepts sums of at most 1000 terms, which bounds the
  chain's Lagrangian near N = 200); --quick: 16 32 64.
"""
import math
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import knife_chain  # noqa: E402

STAGES = [("derive", []), ("analyze", []), ("generate", ["-q", "-o"])]


def run_stage(nhc, stage, extra, scene, outdir):
    args = [nhc, stage] + extra + ([outdir] if stage == "generate" else []) + [scene]
    start = time.perf_counter()
    proc = subprocess.run(["/usr/bin/time", "-f", "%M"] + args, stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True)
    seconds = time.perf_counter() - start
    if proc.returncode != 0:
        raise SystemExit(f"frontend_scaling.py: {' '.join(args)} failed: {proc.stderr.strip()}")
    return seconds, int(proc.stderr.strip().splitlines()[-1]) / 1024.0


def main():
    argv = sys.argv[1:]
    quick = "--quick" in argv
    argv = [a for a in argv if a != "--quick"]
    if len(argv) < 2:
        raise SystemExit(__doc__)
    nhc, out = argv[0], argv[1]
    ns = [int(a) for a in argv[2:]] or ([16, 32, 64] if quick else [32, 64, 128, 192])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in ns:
            with open(os.path.join(tmp, f"knife_chain_{n}.toml"), "w") as f:
                f.write(knife_chain.scene_text(n))
            scene = os.path.join(tmp, f"knife_chain_{n}.toml")
            times, peak = {}, 0.0
            for stage, extra in STAGES:
                times[stage], mb = run_stage(nhc, stage, extra, scene, tmp)
                peak = max(peak, mb)
            rows.append((n, times, peak))
            print(f"N={n}: " + ", ".join(f"{s} {t:.2f} s" for s, t in times.items()) +
                  f", peak {peak:.0f} MB", file=sys.stderr)
    total = [(n, sum(t.values())) for n, t, _ in rows]
    (n0, t0), (n1, t1) = total[0], total[-1]
    slope = math.log(t1 / t0) / math.log(n1 / n0) if n1 != n0 else float("nan")
    lines = ["# Front-end scaling (knife-edge chain, Chetaev)", "",
             f"Measured by `bench/frontend_scaling.py` on this machine; wall seconds.", "",
             "| N | derive | analyze | generate | sum | peak MB |", "|---|---|---|---|---|---|"]
    for n, t, peak in rows:
        lines.append(f"| {n} | {t['derive']:.2f} | {t['analyze']:.2f} | {t['generate']:.2f} | "
                     f"{sum(t.values()):.2f} | {peak:.0f} |")
    met = lambda ok: "met" if ok else "not met"  # noqa: E731
    largest_peak = rows[-1][2]
    lines += ["", f"log-log slope of the sum, N = {n0} to {n1}: {slope:.2f}", "",
              "| goal | measured | |", "|---|---|---|",
              f"| slope <= 1.1 (N = {n0} to {n1}) | {slope:.2f} | {met(slope <= 1.1)} |",
              f"| N = {n1} under 10 s | {t1:.2f} s | {met(t1 < 10.0)} |",
              f"| N = {n1} under 500 MB | {largest_peak:.0f} MB | {met(largest_peak < 500.0)} |", ""]
    if n1 < 1024:
        lines.append(f"The goals name N = 1024; this run stops at N = {n1} (see the usage note).")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
