#!/usr/bin/env python3
"""The rigid-body family of the benchmarks: N uniform balls rolling without slipping on
a horizontal plane, neighbours' centres joined by springs.

Ball i (mass m, radius r, moment of inertia J about its centre) has coordinates (x_i, y_i) of its
centre and z-x-z Euler angles (psi_i, th_i, ph_i); every body quantity is a definition, written
as examples/rolling_ball.toml writes one ball:

    R_i = rotz(psi_i) rotx(th_i) rotz(ph_i),  w_i = omega(R_i),  c_i = [x_i, y_i, r],  v_i = c_i',
    T_i = m/2 |v_i|^2 + J/2 |w_i|^2,          vp_i = v_i + w_i x (-r e_z)   (contact point's velocity)

    L = sum_i T_i - sum_{i<N} k/2 |c_{i+1} - c_i - l e_y|^2,   constraints vp_i[1] = vp_i[2] = 0.

5N coordinates, 2N nonholonomic constraints (x_i, y_i dependent). The springs conserve the total
energy sum T_i + V (the scene's [invariants]: an independent check of any run).

Usage: rolling_balls.py OUTDIR N [N ...]   writes OUTDIR/rolling_balls_<N>.toml
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scene_family  # noqa: E402

PARAMETERS = [("m", 1.0), ("r", 0.5), ("J", 0.1), ("k", 2.0), ("l", 1.5)]
T_END = 1.0
RTOL = 1e-8
ATOL = 1e-10


def initial_values(n):
    """Ball i = 1..n at rest angles psi = 0, th = 1 + 0.1 sin i, ph = 0 with rates (psi', th', ph');
    the centre's velocity follows from rolling: with psi = 0 the angular velocity is
    w = (th', -ph' sin th, psi' + ph' cos th) and v = w x (r e_z) = (r w_y, -r w_x, 0)."""
    r = dict(PARAMETERS)["r"]
    out = []
    for i in range(1, n + 1):
        th = 1.0 + 0.1 * math.sin(i)
        rates = (0.5 * math.cos(i), 0.3 * math.sin(2 * i), 1.0 + 0.2 * math.cos(3 * i))  # psi', th', ph'
        wx, wy = rates[1], -rates[2] * math.sin(th)
        out.append({"x": (0.05 * math.sin(i), r * wy), "y": (1.5 * (i - 1), -r * wx),
                    "psi": (0.0, rates[0]), "th": (th, rates[1]), "ph": (0.0, rates[2])})
    return out


def scene_text(n):
    lines = ["# Benchmark scene (bench/rolling_balls.py, generated): %d ball%s rolling without slipping on"
             % (n, "" if n == 1 else "s"),
             "# a plane, neighbours' centres joined by springs. 5N coordinates, 2N constraints.",
             'name = "rolling_balls_%d"' % n]
    coords = []
    for i in range(1, n + 1):
        coords += ["x%d" % i, "y%d" % i, "psi%d" % i, "th%d" % i, "ph%d" % i]
    lines.append("coordinates = [%s]" % ", ".join('"%s"' % c for c in coords))
    springs = ["-k/2*dot(c{1} - c{0} - [0, l, 0], c{1} - c{0} - [0, l, 0])".format(i, i + 1) for i in range(1, n)]
    lines.append('lagrangian = "%s%s"' % ("+".join("T%d" % i for i in range(1, n + 1)), "".join(springs)))
    cons = []
    for i in range(1, n + 1):
        cons += ["vp%d[1]" % i, "vp%d[2]" % i]
    lines.append("constraints = [%s]" % ", ".join('"%s"' % c for c in cons))
    lines.append("dependent = [%s]" % ", ".join('"x%d", "y%d"' % (i, i) for i in range(1, n + 1)))
    lines.append('models = ["chetaev"]')
    lines.append("")
    lines.append("[definitions]")
    for i in range(1, n + 1):
        lines.append('R{0} = "rotz(psi{0})*rotx(th{0})*rotz(ph{0})"'.format(i))
        lines.append('w{0} = "omega(R{0})"'.format(i))
        lines.append('c{0} = "[x{0}, y{0}, r]"'.format(i))
        lines.append('v{0} = "c{0}\'"'.format(i))
        lines.append('T{0} = "m/2*dot(v{0}, v{0}) + J/2*dot(w{0}, w{0})"'.format(i))
        lines.append('vp{0} = "v{0} + cross(w{0}, [0, 0, -r])"'.format(i))
    lines.append("")
    lines += scene_family.parameters_table(PARAMETERS)
    lines.append("")
    lines.append("[initial]")
    lines.append("t0 = 0.0")
    for i, ball in enumerate(initial_values(n), start=1):
        for name in ("x", "y", "psi", "th", "ph"):
            lines.append("%s%d = [%r, %r]" % ((name, i) + ball[name]))
    lines.append("")
    lines += scene_family.simulate_table(T_END, RTOL, ATOL)
    lines.append("")
    lines.append("[invariants]")
    potential = "+".join("k/2*dot(c{1} - c{0} - [0, l, 0], c{1} - c{0} - [0, l, 0])".format(i, i + 1)
                         for i in range(1, n)) or "0"
    lines.append('energy = "%s + %s"' % ("+".join("T%d" % i for i in range(1, n + 1)), potential))
    return "\n".join(lines) + "\n"


def main(argv):
    return scene_family.write_scenes(argv, "rolling_balls", scene_text)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
