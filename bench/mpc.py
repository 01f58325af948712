#!/usr/bin/env python3
"""Model predictive control (docs/mpc.md): per-solve wall time against the controller's period for
the two examples, median and worst, with the machine's load before and after.

  bench/mpc.py [BUILD_DIR] [--append bench/results.md]

Runs `nhc simulate` of examples/wheeled_pendulum_mpc.toml and examples/unicycle_parking_mpc.toml,
reads the CSV's mpc:seconds and mpc:iterations and prints a Markdown section (appended to the
file given with --append)."""
import argparse
import csv
import datetime
import os
import resource
import pathlib
import statistics
import subprocess
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
SCENES = [("wheeled_pendulum_mpc", 0.05), ("unicycle_parking_mpc", 0.1)]


def load():
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default="build")
    parser.add_argument("--append")
    args = parser.parse_args()
    nhc = pathlib.Path(args.build) / "cli" / "nhc"
    before = load()
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for name, period in SCENES:
            out = pathlib.Path(work) / (name + ".csv")
            used = resource.getrusage(resource.RUSAGE_CHILDREN)
            done = subprocess.run([str(nhc), "simulate", str(HERE.parent / "examples" / (name + ".toml")), "-o", str(out)],
                                  capture_output=True, text=True, check=True)
            now = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (now.ru_utime - used.ru_utime) + (now.ru_stime - used.ru_stime)
            line = next(l.strip() for l in done.stdout.splitlines() if "model predictive control:" in l)
            with open(out, newline="") as f:
                table = list(csv.DictReader(f))
            seconds = [float(r["mpc:seconds"]) for r in table]
            iterations = [int(float(r["mpc:iterations"])) for r in table]
            over = sum(1 for s in seconds if s > period)
            rows.append((name, period, len(seconds), statistics.median(seconds), max(seconds),
                         statistics.median(iterations), max(iterations), over, cpu / len(seconds)))
    after = load()
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    lines = [f"## Model predictive control: time per solve against the period (bench/mpc.py, {stamp})", "",
             f"{os.cpu_count()} cores; load average {before} at the start, {after} at the end (wall-clock "
             "times of single solves, mpc:seconds of the CSV; other work on the machine inflates them, the CPU "
             "column does not count the waiting).", "",
             "| scene | period | solves | median solve | worst solve | median / period | solves over the period "
             "| IPOPT iterations median, max | CPU per solve (the process's CPU time / solves: an upper bound) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for name, period, n, med, worst, it_med, it_max, over, cpu in rows:
        lines.append(f"| {name} | {period} s | {n} | {med * 1e3:.1f} ms | {worst * 1e3:.1f} ms | {med / period:.2f} "
                     f"| {over} | {it_med:g}, {it_max} | {cpu * 1e3:.1f} ms |")
    lines.append("")
    text = "\n".join(lines) + "\n"
    print(text)
    if args.append:
        with open(args.append, "a") as f:
            f.write("\n" + text)


if __name__ == "__main__":
    main()
