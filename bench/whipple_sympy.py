#!/usr/bin/env python3
"""The Whipple bicycle benchmark (Meijaard et al., Proc. R. Soc. A 463 (2007), Table 2): time
`nhc linearize` (derive, reduce, linearize, eigenvalues at v = 5 m/s) against SymPy's
`sympy.physics.mechanics.tests.test_kane3.test_bicycle` (Kane's equations of the same bicycle,
linearized symbolically in v and checked against the benchmark's A matrix), and check nhc's
eigenvalues against Table 2. Results: bench/whipple.md.

Usage: bench/whipple_sympy.py [NHC] [SCENE]   (defaults: build/cli/nhc,
examples/whipple/whipple_bicycle.toml). Without SymPy (Debian python3-sympy) the SymPy part is
skipped with a message; nhc is still timed.
"""
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Table 2 of Meijaard et al. (2007), v = 5 m/s: castering, weave pair, capsize.
TABLE2 = [complex(-14.07838969279822, 0), complex(-0.77534188219585, 4.46486771378823),
          complex(-0.77534188219585, -4.46486771378823), complex(-0.32286642900409, 0)]


def time_nhc(nhc, scene):
    start = time.perf_counter()
    out = subprocess.run([nhc, "linearize", scene, "--at", "phi'=0", "--format", "json"],
                         check=True, capture_output=True, text=True).stdout
    seconds = time.perf_counter() - start
    eigenvalues = [complex(e["re"], e["im"]) for e in json.loads(out)["eigenvalues"]]
    worst = 0.0
    for want in TABLE2:
        got = min(eigenvalues, key=lambda e: abs(e - want))
        worst = max(worst, abs(got - want) / abs(want))
    return seconds, worst


def time_sympy():
    try:
        start = time.perf_counter()
        from sympy.physics.mechanics.tests import test_kane3
        import sympy
    except ImportError:
        return None
    imported = time.perf_counter()
    test_kane3.test_bicycle()
    return sympy.__version__, imported - start, time.perf_counter() - imported


def main():
    nhc = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "cli", "nhc")
    scene = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "examples", "whipple", "whipple_bicycle.toml")
    seconds, worst = time_nhc(nhc, scene)
    print(f"nhc linearize (derive to eigenvalues at v = 5): {seconds:.1f} s; "
          f"largest relative difference from Table 2: {worst:.1e}")
    sympy_result = time_sympy()
    if sympy_result is None:
        print("SymPy not installed (Debian python3-sympy): its test_bicycle is skipped")
        return
    version, import_seconds, test_seconds = sympy_result
    print(f"SymPy {version} test_kane3.test_bicycle: {test_seconds:.1f} s (import {import_seconds:.1f} s)")


if __name__ == "__main__":
    main()
