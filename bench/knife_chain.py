#!/usr/bin/env python3
"""The scalable scene family of the benchmarks: a chain of N knife edges on an inclined plane.

Knife edge i has coordinates (x_i, y_i, theta_i) in the plane (x down the slope), mass m and
moment of inertia J about its vertical axis; it may not slide sideways:

    f_i = x_i' sin(theta_i) - y_i' cos(theta_i) = 0          (first order, nonholonomic)

Gravity pulls along the incline (g sin(alpha) in +x). Neighbours i, i+1 are joined by a
zero-rest-length spring whose anchor points are a distance l apart across the slope:

    L = sum_i [ m/2 (x_i'^2 + y_i'^2) + J/2 theta_i'^2 + m g sin(alpha) x_i ]
        - sum_{i<N} k/2 [ (x_{i+1} - x_i)^2 + (y_{i+1} - y_i - l)^2 ]

3N coordinates, N constraints. Chetaev's model of first-order constraints is the Lagrange
equations with multipliers, which SymPy's LagrangesMethod derives (bench/peers.py).

Usage: knife_chain.py OUTDIR N [N ...]   writes OUTDIR/knife_chain_<N>.toml
The family's definition (parameters, initial values, t_end, tolerances) lives here only: the
scene files, the SymPy/SciPy peers and the hand-written limit (bench/knife_chain_handwritten.hpp,
whose defaults must equal PARAMETERS) all take it from this module.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scene_family  # noqa: E402

# Parameter values, in the order of the scene file.
PARAMETERS = [("m", 1.0), ("J", 0.1), ("g", 9.81), ("alpha", 0.3), ("k", 10.0), ("l", 1.0)]
T_END = 1.0
RTOL = 1e-8
ATOL = 1e-10


def initial_values(n):
    """Initial state of knife edge i = 1..n: (x, x', y, theta, theta'). y' follows from the
    constraint, y' = x' tan(theta); the scenes leave it to nhc's consistent initialization."""
    out = []
    for i in range(1, n + 1):
        x = 0.1 * math.sin(i)
        xd = 1.0 + 0.1 * math.cos(2 * i)
        y = (i - 1) * 1.0 + 0.05 * math.sin(3 * i)
        th = 0.4 * math.sin(0.7 * i)
        thd = 0.5 * math.cos(1.3 * i)
        out.append((x, xd, y, th, thd))
    return out


def consistent_velocities(n):
    """(x', y', theta') of every knife edge at t0, on the constraints."""
    return [(xd, xd * math.tan(th), thd) for (_, xd, _, th, thd) in initial_values(n)]


def scene_text(n):
    lines = []
    lines.append("# Benchmark scene (bench/knife_chain.py, generated): %d knife edge%s on an inclined"
                 % (n, "" if n == 1 else "s"))
    lines.append("# plane, neighbours coupled by springs. 3N coordinates, N first-order constraints.")
    lines.append('name = "knife_chain_%d"' % n)
    coords = []
    for i in range(1, n + 1):
        coords += ["x%d" % i, "y%d" % i, "th%d" % i]
    lines.append("coordinates = [%s]" % ", ".join('"%s"' % c for c in coords))
    # Without spaces: the scene reader takes expressions of at most 100000 characters, and the
    # Lagrangian of N = 1024 has 92500 this way.
    kinetic = []
    for i in range(1, n + 1):
        kinetic.append("m/2*(x{0}'^2+y{0}'^2)+J/2*th{0}'^2+m*g*sin(alpha)*x{0}".format(i))
    springs = []
    for i in range(1, n):
        springs.append("-k/2*((x{1}-x{0})^2+(y{1}-y{0}-l)^2)".format(i, i + 1))
    lines.append('lagrangian = "%s%s"' % ("+".join(kinetic), "".join(springs)))
    cons = ["x{0}'*sin(th{0}) - y{0}'*cos(th{0})".format(i) for i in range(1, n + 1)]
    lines.append("constraints = [%s]" % ", ".join('"%s"' % c for c in cons))
    lines.append('models = ["chetaev"]')
    lines.append("")
    lines += scene_family.parameters_table(PARAMETERS)
    lines.append("")
    lines.append("[initial]")
    lines.append("t0 = 0.0")
    for i, (x, xd, y, th, thd) in enumerate(initial_values(n), start=1):
        lines.append("x%d = [%r, %r]" % (i, x, xd))
        lines.append("y%d = [%r]" % (i, y))
        lines.append("th%d = [%r, %r]" % (i, th, thd))
    lines.append("")
    lines += scene_family.simulate_table(T_END, RTOL, ATOL)
    return "\n".join(lines) + "\n"


def main(argv):
    return scene_family.write_scenes(argv, "knife_chain", scene_text)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
