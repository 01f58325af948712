"""Numbers of the experiment written through the parameters (a contact's mu, the controller's
period, [simulate]'s t_end, tolerances and steps) follow --set, Python's set= and a parameter
study; a value the place does not allow is refused there; and --sensitivity differentiates the
start where [initial] is written through the parameter. Each against a closed form
(docs/combinations.md, "Numbers written through parameters")."""
import csv
import math
import os
import re
import subprocess

import numpy as np
import pytest

import nhc

M, R, G, K = 2.0, 0.3, 9.81, 1.0

# A uniform cylinder rolling on a level floor under the torque T = k t on its angle; its contact's
# friction coefficient is the parameter muT. Rolling, x'' = 2 k t / (3 m r) and the friction the
# floor must give is m x'' = 2 k t / (3 r): the contact slips where that reaches mu m g,
#   t_slip = 3 mu m g r / (2 k)                      (docs/contacts.md, "Rolling under a torque").
CYLINDER = f"""
name = "cylinder"
coordinates = ["x", "th"]
lagrangian = "m/2*x'^2 + m*r^2/4*th'^2"
constraints = ["x' - r*th'"]
models = ["chetaev"]
[parameters]
m = {M}
r = {R}
g = {G}
k = {K}
muT = 0.05
[inputs]
T = "k*t"
[forces]
th = "T"
[initial]
x = [0.0, 0.0]
th = [0.0, 0.0]
[simulate]
t_end = 4.0
rtol = 1e-10
atol = 1e-12
[contacts.floor]
normal = "m*g"
rolling = [1]
mu = "muT"
"""


def slip_time(mu: float) -> float:
    return 3 * mu * M * G * R / (2 * K)


def nhc_command() -> str:
    program = os.environ.get("NHC_EXECUTABLE")
    if not program:
        pytest.skip("NHC_EXECUTABLE is not set (ctest sets it)")
    return program


def simulate(path, *flags, cwd=None):
    return subprocess.run([nhc_command(), "simulate", str(path), *flags], capture_output=True, text=True, cwd=cwd)


def read_csv(path):
    with open(path) as stream:
        rows = list(csv.DictReader(stream))
    return {name: np.array([float(r[name]) for r in rows]) for name in rows[0]}


@pytest.fixture
def cylinder(tmp_path):
    path = tmp_path / "cylinder.toml"
    path.write_text(CYLINDER)
    return path


@pytest.mark.parametrize("mu", [0.2, 0.1])
def test_set_moves_a_contacts_mu(cylinder, tmp_path, mu):
    """--set muT=… with mu = "muT": the slip at 3 mu m g r / (2 k) of the value set (the scene's
    0.05 would slip at 0.44), and the summary says the mu the run used."""
    done = simulate(cylinder, "--set", f"muT={mu}", "-o", str(tmp_path / "run.csv"))
    assert done.returncode == 0, done.stderr
    t = float(re.search(r"contact floor slips at t = (\S+)", done.stdout).group(1))
    assert abs(t - slip_time(mu)) < 1e-8, (t, slip_time(mu))
    assert f"mu = {mu:g})" in done.stdout, done.stdout
    assert abs(read_csv(tmp_path / "run.csv")["t"][-1] - slip_time(mu)) < 1e-8


def test_python_set_and_a_study_over_mu_move_the_slip(cylinder):
    """set= (Scene.load) and a study over muT (one compiled model for every set=): each run slips at
    the closed form of its own mu."""
    for mu in (0.2, 0.1):
        run = nhc.Scene.load(cylinder, set={"muT": mu}).build().simulate()
        assert [e.name for e in run.events] == ["floor.slip"]
        assert abs(run.events[0].t - slip_time(mu)) < 1e-8
    study = np.linspace(0.05, 0.25, 5)
    times = [nhc.Scene.load(cylinder, set={"muT": float(mu)}).build().simulate().events[0].t for mu in study]
    assert np.max(np.abs(np.array(times) - slip_time(study))) < 1e-8, times


def test_a_value_the_place_does_not_allow_is_refused_there(cylinder, tmp_path):
    """mu = "muT" at muT = -0.1 is a negative friction coefficient: exit 2 at mu's place in the file,
    in the same words from Python; --set mu=… names mu's place and what to write instead; an
    ensemble refuses a number its runs share (t_end) written through the varied parameter in words."""
    line, column = next((i + 1, l.index('"muT"') + 1) for i, l in enumerate(CYLINDER.splitlines())
                        if l.startswith("mu = "))
    done = simulate(cylinder, "--set", "muT=-0.1")
    assert done.returncode == 2
    assert done.stderr.startswith(f"{cylinder}:{line}:{column}: "), done.stderr
    assert 'mu = "muT" is -0.1 at muT = -0.1: mu must not be negative' in done.stderr
    with pytest.raises(nhc.SceneError, match=re.escape('mu = "muT" is -0.1 at muT = -0.1: mu must not be negative')):
        nhc.Scene.load(cylinder, set={"muT": -0.1})
    done = simulate(cylinder, "--set", "mu=0.2")
    assert done.returncode == 2
    assert "'mu' is not a parameter of the scene (parameters: " in done.stderr
    assert f"it is the scene's mu of contact 'floor' ({cylinder}:{line}:{column}), written \"muT\": set the " \
           "parameters it uses" in done.stderr, done.stderr
    plain = tmp_path / "plain.toml"
    plain.write_text(CYLINDER.replace('mu = "muT"', "mu = 0.3"))
    done = simulate(plain, "--set", "mu=0.2")
    assert done.returncode == 2 and "to move it with --set, write it there through a parameter" in done.stderr
    # nhc ensemble: a number of the experiment its runs share written through the varied parameter
    # is refused (a varied mu is each run's own: test_ensemble_engine.py).
    spring = tmp_path / "spring.toml"
    spring.write_text('name = "spring"\ncoordinates = ["x"]\nlagrangian = "x\'^2/2 - x^2/2"\n'
                      '[parameters]\nTend = 2.0\n[initial]\nx = [1.0, 0.0]\n[simulate]\nt_end = "Tend"\n')
    done = subprocess.run([nhc_command(), "ensemble", str(spring), "--vary", "Tend=1:2:3",
                           "-o", str(tmp_path / "e.h5")], capture_output=True, text=True)
    assert done.returncode == 2 and "the scene's [simulate] t_end" in done.stderr, done.stderr
    assert "written through 'Tend'" in done.stderr and not (tmp_path / "e.h5").exists()


# x'' = U with U held by a sampled controller whose state z counts time in steps of its period
# (z_{k+1} = z_k + period, U = z): U = t_k on [t_k, t_k + h), so by hand
#   v_{k+1} = v_k + t_k h,  x_{k+1} = x_k + v_k h + t_k h^2 / 2.
CLOCK = """
name = "clock"
coordinates = ["x"]
lagrangian = "x'^2/2"
[parameters]
h = 0.1
[inputs]
U = "0"
[forces]
x = "U"
[initial]
x = [0.0, 0.0]
[simulate]
t_end = 2.0
rtol = 1e-10
atol = 1e-12
[controller]
period = "h"
states = { z = 0.0 }
inputs = { U = "z" }
update = { z = "z + period" }
"""


def clock_by_hand(h, t_end):
    n = round(t_end / h)
    x, v, rows = 0.0, 0.0, [(0.0, 0.0)]
    for k in range(n):
        t = k * h
        x, v = x + v * h + t * h * h / 2, v + t * h
        rows.append(((k + 1) * h, x))
    return np.array(rows)


def test_a_controller_period_written_through_a_parameter(tmp_path):
    """period = "h", --set h=0.25 (Python set=): samples at k/4, the state z (z + period) counts
    time with the period set, and x follows the held input by hand."""
    path = tmp_path / "clock.toml"
    path.write_text(CLOCK)
    done = simulate(path, "--set", "h=0.25", "-o", str(tmp_path / "clock.csv"))
    assert done.returncode == 0, done.stderr
    assert "sampled controller: period 0.25," in done.stdout
    run = read_csv(tmp_path / "clock.csv")
    ref = clock_by_hand(0.25, 2.0)
    assert len(run["t"]) == len(ref) and np.max(np.abs(run["t"] - ref[:, 0])) < 1e-12
    assert np.max(np.abs(run["controller:z"] - run["t"])) < 1e-12  # z + period with the period set
    assert np.max(np.abs(run["x"] - ref[:, 1])) < 1e-8
    py = nhc.Scene.load(path, set={"h": 0.25}).build().simulate()
    assert np.max(np.abs(py.t - ref[:, 0])) < 1e-12 and np.max(np.abs(py["x"] - ref[:, 1])) < 1e-8


OSCILLATOR = """
name = "oscillator"
coordinates = ["x"]
lagrangian = "x'^2/2 - x^2/2"
[parameters]
Tend = 3.0
tol = 1e-10
hmax = 0.5
h0 = 1e-3
[initial]
x = [1.0, 0.0]
[simulate]
t_end = "Tend"
rtol = "tol"
atol = "tol/100"
max_step = "hmax"
initial_step = "h0"
"""


def steps_of(stdout):
    return int(re.search(r"steps (\d+),", stdout).group(1))


def test_simulate_numbers_written_through_parameters(tmp_path):
    """[simulate] t_end, rtol, atol, max_step and initial_step as expressions of the parameters:
    --set Tend=5 runs to t = 5 (cos t to 1e-7), --set hmax=0.01 takes at least 500 steps; a value
    the key does not allow is refused at the key."""
    path = tmp_path / "oscillator.toml"
    path.write_text(OSCILLATOR)
    done = simulate(path, "--set", "Tend=5", "-o", str(tmp_path / "o.csv"))
    assert done.returncode == 0, done.stderr
    run = read_csv(tmp_path / "o.csv")
    assert run["t"][-1] == 5.0 and np.max(np.abs(run["x"] - np.cos(run["t"]))) < 1e-7
    wide = steps_of(done.stdout)
    done = simulate(path, "--set", "Tend=5", "--set", "hmax=0.01")
    assert done.returncode == 0, done.stderr
    assert steps_of(done.stdout) >= 500 > wide, (steps_of(done.stdout), wide)
    py = nhc.Scene.load(path, set={"Tend": 5.0, "hmax": 0.01}).build().simulate()
    assert py.t[-1] == 5.0 and np.max(np.abs(py["x"] - np.cos(py.t))) < 1e-7
    for flag, words in (("tol=2", 'rtol = "tol" is 2 at tol = 2: rtol is not below 1'),
                        ("hmax=0", 'max_step = "hmax" is 0 at hmax = 0: max_step must be positive'),
                        ("h0=-1", 'initial_step = "h0" is -1 at h0 = -1: initial_step must be positive'),
                        ("Tend=-1", 't_end = "Tend" is -1, not after t0 = 0: give --t-end or other parameter values')):
        done = simulate(path, "--set", flag)
        key = words.split(" ")[0]
        line = next(i + 1 for i, l in enumerate(OSCILLATOR.splitlines()) if l.startswith(key + " = "))
        assert done.returncode == 2 and done.stderr.startswith(f"{path}:{line}:"), done.stderr
        assert words in done.stderr, done.stderr


def test_max_step_and_initial_step_keys_are_checked_when_read(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(OSCILLATOR.replace('max_step = "hmax"', "max_step = 0"))
    done = simulate(path)
    assert done.returncode == 2 and "max_step must be positive" in done.stderr, done.stderr


# --sensitivity of a parameter the start is written through: x'' = -w^2 x from x(0) = A, x'(0) = 0
# is x = A cos(w t), so dx/dA = cos(w t); with x(0) = w as well (the parameter in the equations
# and in the start), x = w cos(w t) and dx/dw = cos(w t) - w t sin(w t).
STARTED = """
name = "started"
coordinates = ["x"]
lagrangian = "x'^2/2 - w^2*x^2/2"
[parameters]
A = 2.0
w = 1.5
[initial]
x = ["{start}", 0.0]
[simulate]
t_end = 3.0
rtol = 1e-10
atol = 1e-12
"""


@pytest.mark.parametrize("name,start,closed", [
    ("A", "A", lambda t, w: np.cos(w * t)),
    ("w", "w", lambda t, w: np.cos(w * t) - w * t * np.sin(w * t)),
])
def test_sensitivity_of_a_parameter_the_start_is_written_through(tmp_path, name, start, closed):
    """d(x)/d(A) = cos(w t) (A only in [initial]; refused before) and d(x)/d(w) with w in both: the
    closed form, central differences of two --set runs, and Python's sensitivity= alike."""
    path = tmp_path / "started.toml"
    path.write_text(STARTED.format(start=start))
    done = simulate(path, "--sensitivity", name, "-o", str(tmp_path / "s.csv"))
    assert done.returncode == 0, done.stderr
    run = read_csv(tmp_path / "s.csv")
    column = f"d(x)/d({name})"
    assert np.max(np.abs(run[column] - closed(run["t"], 1.5))) < 1e-6
    value, step = {"A": 2.0, "w": 1.5}[name], 1e-5
    plus, minus = (read_csv_after(path, tmp_path, f"{name}={value + s}") for s in (step, -step))
    assert np.max(np.abs(run[column] - (plus["x"] - minus["x"]) / (2 * step))) < 1e-5
    py = nhc.Scene.load(path).build().simulate(sensitivity=[name])
    assert np.max(np.abs(py[column] - closed(py.t, 1.5))) < 1e-6


def read_csv_after(path, tmp_path, assignment):
    out = tmp_path / f"set_{assignment}.csv"
    done = simulate(path, "--set", assignment, "-o", str(out))
    assert done.returncode == 0, done.stderr
    return read_csv(out)


def test_an_event_threshold_written_through_a_parameter(tmp_path):
    """when = "x - c" on x = cos t: --set c=0.5 (Python set=) records the crossing at acos(0.5)."""
    path = tmp_path / "threshold.toml"
    path.write_text(OSCILLATOR.replace("[parameters]", "[parameters]\nc = 0.9") +
                    '[events]\nlevel = { when = "x - c", direction = "down", action = "record" }\n')
    done = simulate(path, "--set", "c=0.5", "-o", str(tmp_path / "e.csv"))
    assert done.returncode == 0, done.stderr
    with open(tmp_path / "e.events.csv") as stream:
        rows = list(csv.DictReader(stream))
    assert [r["name"] for r in rows] == ["level"] and abs(float(rows[0]["t"]) - math.acos(0.5)) < 1e-8
    run = nhc.Scene.load(path, set={"c": 0.5}).build().simulate()
    assert [e.name for e in run.events] == ["level"] and abs(run.events[0].t - math.acos(0.5)) < 1e-8


def test_a_start_time_written_through_a_parameter(tmp_path):
    """[initial] t0 = "T0" without [simulate] t_end: --set T0=2 runs from 2 to 3 (a run lasts 1
    from t0), x = cos(t - t0)."""
    path = tmp_path / "late.toml"
    path.write_text('name = "late"\ncoordinates = ["x"]\nlagrangian = "x\'^2/2 - x^2/2"\n[parameters]\nT0 = 0.5\n'
                    '[initial]\nt0 = "T0"\nx = [1.0, 0.0]\n')
    done = simulate(path, "--set", "T0=2", "-o", str(tmp_path / "late.csv"), "--rtol", "1e-10", "--atol", "1e-12")
    assert done.returncode == 0, done.stderr
    run = read_csv(tmp_path / "late.csv")
    assert run["t"][0] == 2.0 and run["t"][-1] == 3.0
    assert np.max(np.abs(run["x"] - np.cos(run["t"] - 2.0))) < 1e-7


LATE = ('name = "late"\ncoordinates = ["x"]\nlagrangian = "x\'^2/2 - x^2/2"\n[parameters]\nT0 = 0.5\n'
        '[initial]\nt0 = "T0"\nx = [1.0, 0.0]\n')


def test_output_times_are_checked_against_the_start_set(tmp_path):
    """--output-times (Python output_times=) against the t0 the run takes: [initial] t0 = "T0" at
    0.5 as written, --set T0=-1 moves it, so times from -1 on are the run's, x = cos(t + 1); times
    before the moved t0 are refused (exit 2 naming the flag), though they are after the written one."""
    path = tmp_path / "late.toml"
    path.write_text(LATE)
    times = [-1.0, -0.5, 0.0, 0.25]
    done = simulate(path, "--set", "T0=-1", "--output-times", ",".join(repr(t) for t in times), "-o",
                    str(tmp_path / "early.csv"), "--rtol", "1e-10", "--atol", "1e-12")
    assert done.returncode == 0, done.stderr
    run = read_csv(tmp_path / "early.csv")
    assert list(run["t"]) == times
    assert np.max(np.abs(run["x"] - np.cos(run["t"] + 1.0))) < 1e-7
    python = nhc.Scene.load(path, set={"T0": -1.0}).build().simulate(output_times=times, rtol=1e-10, atol=1e-12)
    assert list(python["t"]) == times
    assert np.max(np.abs(python["x"] - np.cos(python["t"] + 1.0))) < 1e-7

    # Valid for the written t0 (0.5), not for the moved one (2).
    refused = simulate(path, "--set", "T0=2", "--output-times", "1,2.5", "-o", str(tmp_path / "late.csv"))
    assert refused.returncode == 2, refused.stderr
    assert "--output-times 1,2.5: the first time is before t0 = 2" in refused.stderr, refused.stderr
    assert not (tmp_path / "late.csv").exists()
    with pytest.raises(nhc.SceneError, match=r"output_times \[1, 2.5\]: the first time is before t0 = 2"):
        nhc.Scene.load(path, set={"T0": 2.0}).build().simulate(output_times=[1.0, 2.5])
    # And the moved t0 itself: every time must be after it.
    refused = simulate(path, "--set", "T0=3", "--output-times", "3")
    assert refused.returncode == 2 and "--output-times 3: the last time must be after t0 = 3" in refused.stderr, \
        refused.stderr


def test_animate_checks_output_times_against_the_start_set(tmp_path):
    """nhc animate takes the run flags of nhc simulate: --output-times against the t0 --set gives."""
    path = tmp_path / "late.toml"
    path.write_text(LATE + '[visual]\nbob = { shape = "sphere", center = "[x, 0, 0]", radius = 0.1 }\n')
    done = subprocess.run([nhc_command(), "animate", str(path), "--set", "T0=-1", "--output-times", "-1,-0.5,0",
                           "-o", str(tmp_path / "page")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "page" / "index.html").stat().st_size > 0
    refused = subprocess.run([nhc_command(), "animate", str(path), "--set", "T0=2", "--output-times", "1,2.5",
                              "-o", str(tmp_path / "late")], capture_output=True, text=True)
    assert refused.returncode == 2 and "--output-times 1,2.5: the first time is before t0 = 2" in refused.stderr, \
        refused.stderr
    assert not (tmp_path / "late").exists()
