#!/usr/bin/env python3
"""Long runs of the variational integrator against IDA: writes bench/variational.md and
the pictures in docs/variational/.

For each case (the rolling ball, a wobbling rolling disk, the frictionless Chaplygin sleigh) the
variational integrator runs 10^4 steps and a long span of at least 10^6 steps (and at least 10^4
periods where the motion has one); the energy error max_t |E(t) - E(t0)| of each run is what
`nhc simulate` reports (the maximum over its output samples). IDA runs the long span at rtol 1e-6 …
1e-10; the one whose integration time is closest to the variational run's is IDA "at equal cost",
and it also runs the 10^4-step span. `nhc report --integrators ida,variational` then draws the
energy error against t of both long runs on the same axes.

Usage: bench/variational.py [--nhc build/cli/nhc] [--out bench/variational.md] [--quick]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# name, scene, extra flags, step, long span, period (None: no period)
CASES = [
    ("rolling ball", "examples/rolling_ball.toml", [], 0.0125, 31500.0, 3.14159),
    ("rolling disk, wobbling", "bench/variational/rolling_disk_wobble.toml", [], 0.01, 10000.0, 0.935),
    ("Chaplygin sleigh without friction", "examples/chaplygin_sleigh.toml", ["--set", "b=0", "--set", "k=0"],
     0.01, 10000.0, None),
]
IDA_RTOLS = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10]


def simulate(nhc, scene, flags, t_end, outputs, run_flags):
    command = [nhc, "simulate", os.path.join(ROOT, scene), *flags, "--t-end", repr(t_end), "--outputs",
               str(outputs), "--max-steps", "100000000", *run_flags]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit("bench/variational.py: " + " ".join(command) + " failed:\n" + done.stderr)
    text = done.stdout
    drift = re.search(r"invariant energy: max change (\S+)", text)
    seconds = re.search(r"integrate (\S+) s", text)
    steps = re.search(r"steps (\d+)", text)
    return {"energy": float(drift.group(1)), "seconds": float(seconds.group(1)), "steps": int(steps.group(1))}


def fmt(x, digits=3):
    return f"{x:.{digits}g}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nhc", default=os.path.join(ROOT, "build", "cli", "nhc"))
    parser.add_argument("--out", default=os.path.join(ROOT, "bench", "variational.md"))
    parser.add_argument("--pictures", default=os.path.join(ROOT, "docs", "variational"))
    parser.add_argument("--quick", action="store_true", help="spans 100 times shorter (a check of the script)")
    args = parser.parse_args()
    scale = 0.01 if args.quick else 1.0
    rows, pictures = [], []
    for name, scene, flags, h, span, period in CASES:
        span *= scale
        short_t = 1e4 * h
        outputs_long = min(100000, int(round(span / h)))
        var_short = simulate(args.nhc, scene, flags, short_t, 10000, ["--integrator", "variational", "--step", repr(h)])
        var_long = simulate(args.nhc, scene, flags, span, outputs_long, ["--integrator", "variational", "--step", repr(h)])
        ida = {}
        for rtol in IDA_RTOLS:
            ida[rtol] = simulate(args.nhc, scene, flags, span, outputs_long, ["--rtol", repr(rtol), "--atol", repr(rtol * 1e-2)])
            print(f"{name}: IDA rtol {rtol:g}: {ida[rtol]}", file=sys.stderr)
        equal = min(IDA_RTOLS, key=lambda r: abs(ida[r]["seconds"] - var_long["seconds"]))
        ida_short = simulate(args.nhc, scene, flags, short_t, 10000, ["--rtol", repr(equal), "--atol", repr(equal * 1e-2)])
        rows.append((name, h, span, period, var_short, var_long, equal, ida_short, ida[equal], ida))
        print(f"{name}: variational {var_short} / {var_long}; IDA at rtol {equal:g}", file=sys.stderr)

        # The picture: both long runs' energy error against t (nhc report).
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "report")
            command = [args.nhc, "report", os.path.join(ROOT, scene), *flags, "-q", "--integrators", "ida,variational",
                       "--jacobian", "dense", "--projection", "off", "--tolerances", "1e-6:1e-8", "--long-run",
                       repr(span), "--long-run-step", repr(h), "--long-run-rtol", repr(equal), "-o", out]
            subprocess.run(command, check=True, capture_output=True)
            stem = re.sub(r"[^a-z]+", "_", name.lower()).strip("_")
            if not args.quick:
                os.makedirs(args.pictures, exist_ok=True)
                shutil.copy(os.path.join(out, "energy.svg"), os.path.join(args.pictures, stem + "_energy.svg"))
                pictures.append((name, stem + "_energy.svg"))

    with open(args.out, "w") as f:
        f.write("# Variational integrator against IDA: energy error over long runs\n\n")
        f.write(f"Written by `bench/variational.py` on {time.strftime('%Y-%m-%d')} "
                f"({'quick: spans 100 times shorter' if args.quick else 'full spans'}), one run each, "
                f"`nhc simulate` Release build on this machine ({os.cpu_count()} cores). "
                "Energy error: max |E(t) − E(t0)| over the run's output samples (every step for 10^4 steps, "
                "every span/10^5 for the long span); seconds: integration wall time (consistent "
                "initialization included, compilation not). IDA at equal cost: of rtol 1e-6 … 1e-10 "
                "(atol = rtol/100), the one whose long run took the time closest to the variational run's.\n\n")
        f.write("| case | step h | long span (periods) | variational: 10^4 steps | variational: long span "
                "(steps, s) | growth | IDA rtol | IDA: 10^4·h span | IDA: long span (steps, s) | growth |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|\n")
        for name, h, span, period, vs, vl, rtol, i_s, i_l, _ in rows:
            periods = f"{span / period:.0f}" if period else "no period"
            f.write(f"| {name} | {h:g} | {span:g} ({periods}) | {fmt(vs['energy'])} | {fmt(vl['energy'])} "
                    f"({vl['steps']}, {fmt(vl['seconds'])}) | {fmt(vl['energy'] / vs['energy'], 2)}× | {rtol:g} | "
                    f"{fmt(i_s['energy'])} | {fmt(i_l['energy'])} ({i_l['steps']}, {fmt(i_l['seconds'])}) | "
                    f"{fmt(i_l['energy'] / max(i_s['energy'], 1e-300), 2)}× |\n")
        f.write("\nIDA over the long span at every rtol (energy error, steps, seconds):\n\n")
        f.write("| case | " + " | ".join(f"rtol {r:g}" for r in IDA_RTOLS) + " |\n")
        f.write("|---|" + "---|" * len(IDA_RTOLS) + "\n")
        for name, *_, ida in rows:
            f.write(f"| {name} | " + " | ".join(
                f"{fmt(ida[r]['energy'])} ({ida[r]['steps']}, {fmt(ida[r]['seconds'])} s)" for r in IDA_RTOLS) + " |\n")
        if pictures:
            f.write("\nThe energy error against t of both long runs (`nhc report --integrators ida,variational "
                    "--long-run …`):\n\n")
            for name, picture in pictures:
                f.write(f"![{name}](../docs/variational/{picture})\n\n")
    print(f"wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
