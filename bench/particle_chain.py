#!/usr/bin/env python3
"""The second scalable scene family of the benchmarks: a chain of N planar particles,
each held at constant speed by a second-order constraint, neighbours coupled by springs.

Particle i has coordinates (x_i, y_i) and unit mass; its acceleration stays perpendicular to its
velocity (the paper's Example 1 in the plane):

    f_i = x_i' x_i'' + y_i' y_i'' = 0                          (second order, nonholonomic)

Neighbours i, i+1 are joined by a zero-rest-length spring whose anchor points are a distance l
apart across the chain (the knife chain's springs, bench/knife_chain.py):

    L = sum_i 1/2 (x_i'^2 + y_i'^2) - sum_{i<N} k/2 [ (x_{i+1} - x_i)^2 + (y_{i+1} - y_i - l)^2 ]

2N coordinates, N constraints. Every model keeps each particle's speed: |q_i'|^2 is constant on
f_i = 0 (the scene's [invariants] list them, an independent check of any run).

Usage: particle_chain.py OUTDIR N [N ...]   writes OUTDIR/particle_chain_<N>.toml
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scene_family  # noqa: E402

PARAMETERS = [("k", 2.0), ("l", 1.0)]
T_END = 1.0
RTOL = 1e-8
ATOL = 1e-10


def initial_values(n):
    """Initial state of particle i = 1..n: (x, x', y, y'), speed 1 + 0.1 sin(i)."""
    out = []
    for i in range(1, n + 1):
        speed = 1.0 + 0.1 * math.sin(i)
        heading = 0.3 * math.sin(0.7 * i)
        out.append((0.1 * math.sin(i), speed * math.cos(heading),
                    (i - 1) * 1.0 + 0.05 * math.sin(3 * i), speed * math.sin(heading)))
    return out


def scene_text(n):
    lines = ["# Benchmark scene (bench/particle_chain.py, generated): %d planar particle%s at constant"
             % (n, "" if n == 1 else "s"),
             "# speed (x'x'' + y'y'' = 0), neighbours coupled by springs. 2N coordinates, N constraints.",
             'name = "particle_chain_%d"' % n]
    coords = []
    for i in range(1, n + 1):
        coords += ["x%d" % i, "y%d" % i]
    lines.append("coordinates = [%s]" % ", ".join('"%s"' % c for c in coords))
    kinetic = ["1/2*(x{0}'^2+y{0}'^2)".format(i) for i in range(1, n + 1)]
    springs = ["-k/2*((x{1}-x{0})^2+(y{1}-y{0}-l)^2)".format(i, i + 1) for i in range(1, n)]
    lines.append('lagrangian = "%s%s"' % ("+".join(kinetic), "".join(springs)))
    cons = ["x{0}'*x{0}'' + y{0}'*y{0}''".format(i) for i in range(1, n + 1)]
    lines.append("constraints = [%s]" % ", ".join('"%s"' % c for c in cons))
    lines.append("dependent = [%s]" % ", ".join('"y%d"' % i for i in range(1, n + 1)))
    lines.append('models = ["chetaev"]')
    lines.append("")
    lines += scene_family.parameters_table(PARAMETERS)
    lines.append("")
    lines.append("[initial]")
    lines.append("t0 = 0.0")
    for i, (x, xd, y, yd) in enumerate(initial_values(n), start=1):
        lines.append("x%d = [%r, %r]" % (i, x, xd))
        lines.append("y%d = [%r, %r]" % (i, y, yd))
    lines.append("")
    lines += scene_family.simulate_table(T_END, RTOL, ATOL)
    lines.append("")
    lines.append("[invariants]")
    for i in range(1, n + 1):
        lines.append("speed%d = \"x%d'^2 + y%d'^2\"" % (i, i, i))
    return "\n".join(lines) + "\n"


def main(argv):
    return scene_family.write_scenes(argv, "particle_chain", scene_text)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
