"""Model predictive control (docs/mpc.md), each result against an independent path: the closed
loop of the wheeled pendulum (its bounds, its end state), the first solve of the loop against a
standalone `nhc optimize` of the same problem from the same state, the command line against
Python, the parked unicycle against SciPy's integration of the inputs the loop held, and the
combinations of docs/combinations.md's section on model predictive control."""
import csv
import os
import pathlib
import re
import subprocess

import numpy as np
import pytest

import nhc

SOURCE = pathlib.Path(os.environ.get("NHC_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
PENDULUM = SOURCE / "examples" / "wheeled_pendulum_mpc.toml"
UNICYCLE = SOURCE / "examples" / "unicycle_parking_mpc.toml"
TABLE = SOURCE / "docs" / "combinations.md"
SUMMARY = re.compile(r"model predictive control: (\d+) solves, median (\S+) s, max (\S+) s, (\d+) not converged")


def nhc_command() -> str:
    program = os.environ.get("NHC_EXECUTABLE")
    if not program:
        pytest.skip("NHC_EXECUTABLE is not set (ctest sets it)")
    return program


def run(args, expect=0):
    done = subprocess.run([nhc_command(), *map(str, args)], capture_output=True, text=True, timeout=600)
    assert done.returncode == expect, done.stdout + done.stderr
    return done


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(x) for x in r] for r in rows[1:]])


def simulate(scene, tmp_path, *flags, name="run.csv"):
    out = tmp_path / name
    done = run(["simulate", scene, "-o", out, *flags])
    header, data = read_csv(out)
    return {h: data[:, k] for k, h in enumerate(header)}, done.stdout


@pytest.fixture(scope="module")
def pendulum(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("pendulum")
    return simulate(PENDULUM, tmp)


def test_pendulum_moved_upright_within_bounds(pendulum):
    c, summary = pendulum
    m = SUMMARY.search(summary)
    assert m, summary
    solves, not_converged = int(m.group(1)), int(m.group(4))
    assert solves == len(c["t"]) == 121  # a solve at every sample 0, 0.05, ..., 6
    assert not_converged == 0
    assert np.all(c["mpc:iterations"] >= 1)
    assert abs(c["t"][-1] - 6.0) < 1e-12
    # At 6 s: at the target position, upright, within the torque bounds at every sample.
    assert abs(c["x"][-1] - 0.5) < 0.01, c["x"][-1]
    assert abs(c["th"][-1]) < 0.02, c["th"][-1]
    for u in ("input:TL", "input:TR"):
        assert np.all(np.abs(c[u]) <= 1.0 + 1e-9)
    # It did move: the start leaned 0.1 rad at x = 0.
    assert c["th"][0] == pytest.approx(0.1) and c["x"][0] == pytest.approx(0.0)


def standalone_scene(tmp_path, text, t_end, start):
    """The scene without [controller], its [optimize] over [t0, t_end] from `start`."""
    text = re.sub(r"\[controller\]\n(?:[^\[\n].*\n|\n)*", "", text)
    text = text.replace("[optimize]\n", f"[optimize]\nt_end = {t_end}\n", 1)
    text += "\n[optimize.initial]\n" + "".join(f'"{k}" = {v!r}\n' for k, v in start.items())
    path = tmp_path / "standalone.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("flags,start", [
    ([], {"th": 0.1}),
    (["--initial", "th=0.05"], {"th": 0.05}),
    (["--set", "mb=2.5"], {"th": 0.1}),
])
def test_first_input_is_the_standalone_optimum(tmp_path, flags, start):
    """The loop's first solve against `nhc optimize` of the same problem (its [optimize] over the
    horizon, the same mesh, no refinement) from the same state: the same cost and first torques."""
    c, _ = simulate(PENDULUM, tmp_path, "--t-end", "0.05", *flags)
    coordinates = ["x", "y", "psi", "th", "phL", "phR"]
    values = {q: 0.0 for q in coordinates}
    values.update(start)
    values.update({q + "'": 0.0 for q in coordinates})
    text = PENDULUM.read_text()
    if "--set" in flags:  # nhc optimize takes no --set: the value written into its scene
        name, value = flags[1].split("=")
        text, n = re.subn(rf"^{name} = \S+$", f"{name} = {value}", text, flags=re.M)
        assert n == 1
    scene = standalone_scene(tmp_path, text, 1.5, values)
    out = tmp_path / "path.csv"
    done = run(["optimize", scene, "--intervals", 15, "--path-tolerance", 1e3, "--tolerance", 1e-10, "-o", out])
    cost = float(re.search(r"cost = (\S+)", done.stdout).group(1))
    assert c["mpc:cost"][0] == pytest.approx(cost, rel=1e-6, abs=1e-8)
    header, data = read_csv(out)
    for u in ("TL", "TR"):
        assert c["input:" + u][0] == pytest.approx(data[0, header.index(u)], abs=1e-5)


def test_python_runs_the_same_loop(pendulum, tmp_path):
    c, _ = pendulum
    run_ = nhc.Scene.load(str(PENDULUM)).build().simulate()
    assert list(run_.columns) == [k for k in c]
    for name in c:
        if name == "mpc:seconds":
            continue  # wall time
        np.testing.assert_allclose(run_[name], c[name], rtol=0, atol=1e-9, err_msg=name)
    assert SUMMARY.search(run_.summary["model_predictive_control"])
    # controller=nhc.Mpc(...) changes it: another horizon, another (still converged) loop.
    other = nhc.Scene.load(str(PENDULUM)).build().simulate(t_end=0.5, controller=nhc.Mpc(horizon=1.0, intervals=10))
    m = SUMMARY.search(other.summary["model_predictive_control"])
    assert m and int(m.group(1)) == 11 and int(m.group(4)) == 0
    assert other["mpc:cost"][0] != pytest.approx(c["mpc:cost"][0])


def unicycle_replay(c):
    """SciPy's integration of the held inputs: m v' = F, J w' = tau, x' = v cos th, y' = v sin th,
    th' = w (the knife edge's constraint force is across the heading), from the scene's start."""
    integrate = pytest.importorskip("scipy.integrate")
    m, J = 1.0, 0.1
    t = c["t"]
    state = np.array([0.0, 0.5, 0.0, 0.0, 0.0])  # x, y, theta, v, w
    states = [state]
    for k in range(len(t) - 1):
        F, tau = c["input:F"][k], c["input:tau"][k]
        f = lambda _, s: [s[3] * np.cos(s[2]), s[3] * np.sin(s[2]), s[4], F / m, tau / J]
        state = integrate.solve_ivp(f, (t[k], t[k + 1]), state, rtol=1e-11, atol=1e-12).y[:, -1]
        states.append(state)
    return np.array(states)


def test_unicycle_parked_from_a_sideways_start(tmp_path):
    c, summary = simulate(UNICYCLE, tmp_path)
    m = SUMMARY.search(summary)
    assert m and int(m.group(4)) == 0, summary
    replay = unicycle_replay(c)
    x, y, th = replay[-1, :3]
    assert np.hypot(x, y) < 0.05, (x, y)
    assert abs(th) < 0.1, th
    # nhc's own run of those inputs agrees with the replay (the loop's plant is the scene's model).
    np.testing.assert_allclose(replay[:, 0], c["x"], atol=1e-6)
    np.testing.assert_allclose(replay[:, 1], c["y"], atol=1e-6)
    assert np.all(np.abs(c["input:F"]) <= 2 + 1e-9) and np.all(np.abs(c["input:tau"]) <= 1 + 1e-9)


def test_events_end_the_loop_where_they_cross(pendulum, tmp_path):
    """A stop event ends the closed loop at its crossing; before it the rows are the loop's without it."""
    c, _ = pendulum
    d, summary = simulate(PENDULUM, tmp_path, "--stop-when", "x - 0.25", name="stop.csv")
    assert d["x"][-1] == pytest.approx(0.25, abs=1e-7)
    n = len(d["t"]) - 1  # the last row is the crossing, between two samples
    assert c["t"][n - 1] < d["t"][-1] < c["t"][n]
    for name in ("x", "th", "input:TL", "input:TR", "mpc:cost"):
        np.testing.assert_allclose(d[name][:n], c[name][:n], rtol=0, atol=1e-9, err_msg=name)
    assert np.isnan(d["mpc:cost"][-1])  # no solve at the crossing


def test_contacts_are_refused_in_words(tmp_path):
    text = UNICYCLE.read_text().replace("[controller]", '[contacts.wheel]\nnormal = "9.81*m"\nrolling = [1]\nmu = 0.8\n\n[controller]')
    scene = tmp_path / "contact.toml"
    scene.write_text(text)
    done = run(["simulate", scene], expect=2)
    assert "plans with the equations of [optimize], which hold no contact force" in done.stderr


def test_the_table_names_tests_that_exist():
    """docs/combinations.md's rows of model predictive control name tests of this file, or of the test file
    the row names beside the test (`test_ensemble_engine.py `test_…``)."""
    section = TABLE.read_text().split("## Model predictive control with the run features", 1)[1].split("\n## ", 1)[0]
    names = re.findall(r"`(test_\w+)", section)
    assert len(names) >= 4
    here = pathlib.Path(__file__).parent
    for row in section.splitlines():
        files = re.findall(r"(test_\w+\.py)", row)
        for name in re.findall(r"`(test_\w+)", row):
            if files:
                assert any(f"def {name}(" in (here / f).read_text() for f in files), (name, files)
            else:
                assert name in globals(), name


def test_commands_that_do_not_run_it_refuse_it(tmp_path):
    done = run(["animate", PENDULUM, "-o", tmp_path / "a.html"], expect=2)
    assert "model predictive control (mpc), which nhc simulate and Python's Model.simulate run" in done.stderr
    done = run(["report", PENDULUM, "-o", tmp_path / "r.md"], expect=2)
    assert "does not run the scene's [controller]" in done.stderr


def test_solves_that_do_not_converge_are_counted_and_hold_the_last_plan():
    """With 2 IPOPT iterations per solve none converges (the first needs 10 from the straight
    line); with 6 the first does not, a later one, warm-started from the last iterate, does, and
    the failures after it hold that plan's inputs. Each failure is counted; the inputs held stay
    within their bounds."""
    for limit, expected in ((2, lambda n: n == 7), (6, lambda n: 1 <= n < 7)):
        run_ = nhc.Scene.load(str(PENDULUM)).build().simulate(
            t_end=0.3, controller=nhc.Mpc(horizon=1.5, intervals=15, max_iterations=limit))
        m = SUMMARY.search(run_.summary["model_predictive_control"])
        assert m and int(m.group(1)) == 7
        assert expected(int(m.group(4))), (limit, m.group(0))
        assert np.all(run_["mpc:iterations"] <= limit)
        for u in ("input:TL", "input:TR"):
            assert np.all(np.abs(run_[u]) <= 1.0 + 1e-9)
