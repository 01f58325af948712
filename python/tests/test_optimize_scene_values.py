"""nhc optimize with the scene's parameter values set from outside (--set, Python set=) and with
[definitions] in its objective, each against the Heisenberg system's closed form (docs/optimize.md):
from (0, 0, 0) to (0, 0, a) in time T the least k/2 int (x'^2 + y'^2) dt is k 2 pi a / T, on a
circle of radius sqrt(a/pi) through the origin (the isoperimetric inequality, scaled by k)."""
import math
import os
import re
import subprocess

import numpy as np
import pytest

import nhc

SCENE = """name = "heisenberg"
coordinates = ["x", "y", "z"]
lagrangian = "1/2*(x'^2 + y'^2)"
constraints = ["z' - (x*y' - y*x')/2"]
models = ["vakonomic"]
[parameters]
a = {a}
k = {k}
T = 1.0
{definitions}
[initial]
x = [0.0]
y = [0.0]
z = [0.0]
[optimize]
objective = "{objective}"
{final_cost}
t_end = "T"
intervals = 40
[optimize.initial]
x = 0.0
y = 0.0
z = 0.0
[optimize.final]
x = 0.0
y = 0.0
z = "a"
"""


def scene_text(a=0.5, k=1.0, definitions="", objective="k*(x'^2 + y'^2)/2", final_cost=""):
    return SCENE.format(a=a, k=k, definitions=definitions, objective=objective, final_cost=final_cost)


def nhc_command():
    program = os.environ.get("NHC_EXECUTABLE")
    if not program:
        pytest.skip("NHC_EXECUTABLE is not set (ctest sets it)")
    return program


def optimize(path, *flags):
    return subprocess.run([nhc_command(), "optimize", str(path), *flags], capture_output=True, text=True)


def cost_of(done):
    assert done.returncode == 0, done.stdout + done.stderr
    return float(re.search(r"^  cost = (\S+)$", done.stdout, re.M).group(1))


def read_csv(path):
    lines = path.read_text().splitlines()
    return lines[0].split(","), np.array([[float(v) for v in line.split(",")] for line in lines[1:]])


def check_loop(columns, data, a, k, t_end=1.0):
    """The path: z(T) = a, and the loop a circle of radius sqrt(a/pi) through the origin."""
    x, y, z = (data[:, columns.index(name)] for name in ("x", "y", "z"))
    assert z[-1] == a and z[0] == 0.0
    r = math.sqrt(a / math.pi)
    centre = np.array([x[:-1].mean(), y[:-1].mean()])  # equally spaced in t at constant speed
    assert abs(np.hypot(*centre) - r) < 1e-4 * r
    assert np.max(np.abs(np.hypot(x - centre[0], y - centre[1]) - r)) < 1e-4 * r


def test_optimize_set_moves_the_optimum(tmp_path):
    """--set a=0.8 --set k=3: cost 3 2 pi 0.8 = 15.08 (the scene's values give pi); the same path
    as the scene file with the values written in it, and as Python's Scene.load(set=)."""
    written = tmp_path / "written.toml"
    written.write_text(scene_text())
    edited = tmp_path / "edited.toml"
    edited.write_text(scene_text(a=0.8, k=3.0))

    moved = optimize(written, "--set", "a=0.8", "--set", "k=3", "-o", str(tmp_path / "set.csv"))
    cost = cost_of(moved)
    assert cost == pytest.approx(3 * 2 * math.pi * 0.8, rel=1e-6)
    columns, data = read_csv(tmp_path / "set.csv")
    check_loop(columns, data, 0.8, 3.0)
    assert cost_of(optimize(written)) == pytest.approx(math.pi, rel=1e-6)  # the scene's own values

    by_hand = optimize(edited, "-o", str(tmp_path / "edited.csv"))
    assert cost_of(by_hand) == cost
    assert (tmp_path / "edited.csv").read_bytes() == (tmp_path / "set.csv").read_bytes()

    run = nhc.Scene.load(written, set={"a": 0.8, "k": 3.0}).optimize()
    assert run.cost == pytest.approx(cost, rel=1e-14)
    assert list(run.columns) == columns
    assert np.array_equal(run.to_numpy(), data)

    # A t_end written through a parameter moves too: T = 2 halves the cost.
    assert cost_of(optimize(written, "--set", "T=2")) == pytest.approx(math.pi / 2, rel=1e-6)


@pytest.mark.parametrize("assignment, words", [
    ("q=1", "--set: error: q=1: 'q' is not a parameter of the scene (parameters: T, a, k)"),
    ("a=fast", "--set: error: "),
    ("a", "--set: error: "),
])
def test_optimize_set_refuses_bad_assignments(tmp_path, assignment, words):
    path = tmp_path / "s.toml"
    path.write_text(scene_text())
    done = optimize(path, "--set", assignment, "-o", str(tmp_path / "path.csv"))
    assert done.returncode == 2, done.stdout + done.stderr
    assert done.stderr.startswith(words) and len(done.stderr.splitlines()) == 1, done.stderr
    assert not (tmp_path / "path.csv").exists()


def test_optimize_objective_uses_a_definition(tmp_path):
    """objective = "k*speed2/2" with speed2 = "x'^2 + y'^2" in [definitions] (and a final cost
    through one): the same optimum as the cost written out, pi; the definitions count as used."""
    definitions = '[definitions]\nspeed2 = "x\'^2 + y\'^2"\nrho2 = "x^2 + y^2"'
    with_definitions = tmp_path / "definitions.toml"
    with_definitions.write_text(scene_text(definitions=definitions, objective="k*speed2/2",
                                           final_cost='final_cost = "rho2"'))
    written_out = tmp_path / "written_out.toml"
    written_out.write_text(scene_text(final_cost='final_cost = "x^2 + y^2"'))

    through = optimize(with_definitions, "-o", str(tmp_path / "definitions.csv"))
    cost = cost_of(through)
    assert "never used" not in through.stderr, through.stderr
    assert cost == pytest.approx(math.pi, rel=1e-6)
    assert cost_of(optimize(written_out, "-o", str(tmp_path / "written_out.csv"))) == cost
    assert (tmp_path / "definitions.csv").read_bytes() == (tmp_path / "written_out.csv").read_bytes()
    columns, data = read_csv(tmp_path / "definitions.csv")
    check_loop(columns, data, 0.5, 1.0)

    run = nhc.Scene.load(with_definitions).optimize()
    assert run.cost == pytest.approx(cost, rel=1e-14)


def test_a_fault_inside_a_definition_the_objective_uses_is_located_there(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(scene_text(definitions='[definitions]\nspeed2 = "x\'^2 + w"', objective="k*speed2/2"))
    done = optimize(path)
    assert done.returncode == 2, done.stdout + done.stderr
    # speed2 is line 11 of the scene text; the unknown name w at its column in that line.
    assert re.search(r"bad\.toml:11:\d+: error: .*unknown name 'w'", done.stderr), done.stderr
