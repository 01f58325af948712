#!/usr/bin/env python3
"""Compile time against run time at each optimization level (bench/compile-time.md).

For every scene and variant, `nhc_bench SCENE --opt LEVEL [--translation-units K]` (a fresh
compile cache each time), the variants interleaved round by round so that a change of the
machine's load hits all of them alike. Prints one Markdown row per scene and variant: header
size, compile (wall, median and range of the rounds), per-call residual and Jacobian (best over
the rounds), the scene's whole integration (best), and the final state's largest difference to
the first variant's, relative to max(|y|, 1) per component.

Usage: bench/opt_levels.py NHC_BENCH ROUNDS SCENE... [-- VARIANT...]
  VARIANT: "-O0", "-O1", "-O2", "-O1 tu2" (two translation units); default -O2 -O1 -O0.
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile


def run(bench, scene, variant, out):
    level, *rest = variant.split()
    command = [bench, scene, "--out", out, "--opt", level]
    for word in rest:
        if word.startswith("tu"):
            command += ["--translation-units", word[2:]]
    done = subprocess.run(command, check=True, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main():
    args = sys.argv[1:]
    variants = ["-O2", "-O1", "-O0"]
    if "--" in args:
        i = args.index("--")
        args, variants = args[:i], args[i + 1:]
    bench, rounds, scenes = args[0], int(args[1]), args[2:]
    print("| scene | header | variant | units | compile s: median (range) | residual µs | Jacobian µs "
          "| integration s | compile + integration s | final state vs first variant |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for scene in scenes:
            results = {v: [] for v in variants}
            for _ in range(rounds):
                for v in variants:
                    results[v].append(run(bench, scene, v, os.path.join(work, "out")))
            reference = results[variants[0]][0]["final_y"]
            for v in variants:
                rs = results[v]
                compile_s = [r["compile_s"] for r in rs]
                med = statistics.median(compile_s)
                residual = min(r["residual_call_s"] for r in rs)
                jacobian = min(r["jacobian_call_s"] for r in rs)
                integrate = min(r["integrate_s"] for r in rs)
                worst = max(abs(a - b) / max(abs(b), 1.0) for r in rs for a, b in zip(r["final_y"], reference))
                print(f"| {rs[0]['scene']} | {rs[0]['header_bytes'] / 1e3:.0f} kB | {v} | {rs[0]['translation_units']} "
                      f"| {med:.2f} ({min(compile_s):.2f}–{max(compile_s):.2f}) | {residual * 1e6:.3g} "
                      f"| {jacobian * 1e6:.3g} | {integrate:.4g} | {med + integrate:.2f} | {worst:.1e} |",
                      flush=True)


if __name__ == "__main__":
    main()
