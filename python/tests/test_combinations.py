"""The interaction matrix (docs/combinations.md): every pair of run features on one system, a
uniform cylinder rolling on a level floor under a torque T on its angle, each working cell against
an independent answer (SciPy's solve_ivp of the same motion written out by hand: rolling,
x'' = (D + T/r)/(3m/2); sliding, m x'' = D - mu m g sgn f, I th'' = T + mu m g r sgn f), each
refused cell's exit code and words. The cells are read from the document's table, so a row added
there is walked here."""
import csv
import json
import os
import pathlib
import re
import subprocess

import numpy as np
import pytest

import nhc

integrate = pytest.importorskip("scipy.integrate")

SOURCE = pathlib.Path(os.environ.get("NHC_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
TABLE = SOURCE / "docs" / "combinations.md"
M, R, G, K, C, V, MU, T_END, H = 2.0, 0.3, 9.81, 1.0, 0.5, 2.0, 0.2, 2.5, 0.1
# `--set` moves g (the normal force m*g), the friction coefficient muT (mu = "muT") and the
# controller's period h (period = "h"): each a number the scene writes through a parameter.
MU_SET, H_SET = 0.3, 0.125


def settings(f):
    """The --set (Python set=) values of a run with the features f."""
    values = {"g": G / 2}
    if "contact stop" in f or "contact slide" in f:
        values["muT"] = MU_SET
    if "controller" in f:
        values["h"] = H_SET
    return values


def nhc_command() -> str:
    program = os.environ.get("NHC_EXECUTABLE")
    if not program:
        pytest.skip("NHC_EXECUTABLE is not set (ctest sets it)")
    return program


def cells():
    """(row feature, column feature, text) for every cell of the table above its diagonal."""
    # The pair table of the section "## The matrix"; the sections after it list other features'
    # cells with their own tests.
    matrix = TABLE.read_text().split("## The matrix", 1)[1].split("\n## ", 1)[0]
    lines = [l for l in matrix.splitlines() if l.startswith("|")]
    header = [h.strip() for h in lines[0].strip("|").split("|")][1:]
    out = []
    for line in lines[2:]:
        parts = [p.strip() for p in line.strip("|").split("|")]
        row = parts[0]
        for col, text in zip(header, parts[1:]):
            if text and text != "·" and header.index(col) > header.index(row):
                out.append((row, col, text))
    return out


def scene_text(f) -> str:
    lines = ['name = "combination"', 'coordinates = ["x", "th"]', "lagrangian = \"m/2*x'^2 + m*r^2/4*th'^2\"",
             "constraints = [\"x' - r*th'\"]", 'models = ["chetaev"]', "[parameters]",
             f"m = {M}", f"r = {R}", f"g = {G}", f"k = {K}", f"c = {C}", f"V = {V}",
             *([f"muT = {MU}"] if "contact stop" in f or "contact slide" in f else []),
             *([f"h = {H}"] if "controller" in f else []),
             "[inputs]", 'T = "k*t"', "D = \"-c*x'\"" if "feedback law" in f else 'D = "0"',
             "[forces]", 'x = "D"', 'th = "T"', "[initial]", "x = [0.0, 0.0]", "th = [0.0, 0.0]",
             "[simulate]", f"t_end = {T_END}", "outputs = 25", "rtol = 1e-10", "atol = 1e-12"]
    if "controller" in f:
        lines += ["[controller]", 'period = "h"', 'inputs = { T = "k*t" }']
    if "events" in f:
        lines += ["[events]", 'mark = { when = "x - 0.05", action = "record" }',
                  "fast = { when = \"x' - V\", direction = \"up\", action = \"stop\" }"]
    if "outputs" in f:
        lines += ["[outputs]", "ke = \"m/2*x'^2 + m*r^2/4*th'^2\""]
    if "contact slide" in f:
        lines += ["[contacts.floor]", 'normal = "m*g"', "rolling = [1]", 'mu = "muT"', 'on_slip = "slide"']
    if "contact stop" in f:  # with a sliding one: a second contact on the same constraint, mu 0.5
        name, mu = ("rim", "0.5") if "contact slide" in f else ("floor", '"muT"')
        lines += [f"[contacts.{name}]", 'normal = "m*g"', "rolling = [1]", f"mu = {mu}", 'on_slip = "stop"']
    return "\n".join(lines) + "\n"


def reference(f, k=K):
    """The motion by hand: rows at the output times (the samples under a controller) up to a stop,
    the events met, as (t, x, x', th, th') rows and (name, t) pairs."""
    g = G / 2 if "--set" in f else G
    inertia = M * R * R / 2
    mu = (MU_SET if "--set" in f else MU) if ("contact stop" in f or "contact slide" in f) else None
    slide = "contact slide" in f
    h = H_SET if "--set" in f else H
    times = np.linspace(0, T_END, round(T_END / h) + 1 if "controller" in f else 26)

    def torque(t, t_held):
        if "controller" in f:
            return k * t_held
        return 0.5 + k * t if "--input" in f else k * t

    def damping(v):
        return -C * v if "feedback law" in f else 0.0

    def rolling_rhs(t, s, th_):
        xdd = (damping(s[1]) + torque(t, th_) / R) / (M + inertia / R**2)
        return [s[1], xdd, s[3], xdd / R]

    def friction_needed(t, s, th_):  # lambda = m x'' - D
        xdd = rolling_rhs(t, s, th_)[1]
        return M * xdd - damping(s[1])

    def sliding_rhs(t, s, th_, sgn):
        return [s[1], (damping(s[1]) - mu * M * g * sgn) / M, s[3], (torque(t, th_) + mu * M * g * R * sgn) / inertia]

    state = np.array([0.0, 0.3, 0.0, 1.0] if "--initial" in f else [0.0, 0.0, 0.0, 0.0])
    rows, events, t, sliding, sgn = [], [], 0.0, False, 0.0
    bounds = list(times) if "controller" in f else [0.0, T_END]
    rows.append([0.0, *state])
    seg = 0
    while seg < len(bounds) - 1:
        t_held, t_next = bounds[seg], bounds[seg + 1]
        if "controller" in f and mu is not None and not sliding:  # the held torque jumps at the sample
            if abs(friction_needed(t, state, t_held)) > mu * M * g:
                events.append(("floor.slip", t))
                if "contact slide" not in f:
                    break
                sliding, sgn = True, -np.sign(friction_needed(t, state, t_held))
        evs, names, kinds = [], [], []
        if "events" in f:
            e1 = lambda tt, s, *a: s[0] - 0.05
            e2 = lambda tt, s, *a: s[1] - V
            e2.terminal, e2.direction = True, 1
            evs += [e1, e2]
            names += ["mark", "fast"]
            kinds += ["record", "stop"]
        if mu is not None and not sliding:
            e3 = lambda tt, s, *a: mu * M * g - abs(friction_needed(tt, s, t_held))
            e3.terminal, e3.direction = True, -1
            evs.append(e3)
            names.append("floor.slip")
            kinds.append("stop" if not slide else "switch")
        if sliding:
            e4 = lambda tt, s, *a: sgn * (s[1] - R * s[3]) - 1e-9
            e4.terminal, e4.direction = True, -1
            evs.append(e4)
            names.append("floor.stick")
            kinds.append("switch")
        rhs = (lambda tt, s: sliding_rhs(tt, s, t_held, sgn)) if sliding else (lambda tt, s: rolling_rhs(tt, s, t_held))
        sol = integrate.solve_ivp(rhs, (t, t_next), state, rtol=1e-12, atol=1e-13, events=evs or None,
                                  dense_output=True, method="DOP853")
        end = sol.t[-1]
        stop_now, switch_now = False, None
        hits = []
        for i, name in enumerate(names):
            for te in sol.t_events[i]:
                if te > t + 1e-12:
                    hits.append((te, name, kinds[i]))
        hits.sort()
        for te, name, kind in hits:
            events.append((name, te))
            if kind == "stop":
                stop_now = True
            elif kind == "switch":
                switch_now = name
        if "controller" not in f:
            for tt in times:
                if t < tt <= end + 1e-12:
                    rows.append([tt, *sol.sol(tt)])
        state = sol.y[:, -1]
        if stop_now:
            rows.append([end, *state])
            break
        if switch_now:
            t = end
            if "controller" not in f:  # the switch's point is a row (the integrator's, where its event ended it)
                rows.append([end, *state])
            if switch_now == "floor.slip":
                sliding, sgn = True, -np.sign(friction_needed(t, state, t_held))
            else:
                sliding = False  # f = 0 there: x' = r th' already
            continue
        t = end
        seg += 1
        if "controller" in f:
            rows.append([t, *state])
    return np.array(rows), events


def run_cli(f, tmp_path):
    path = tmp_path / "combination.toml"
    path.write_text(scene_text(f))
    args = [nhc_command(), "simulate", str(path), "-o", str(tmp_path / "run.csv")]
    if "--input" in f:
        args += ["--input", "T=0.5+k*t"]
    if "--initial" in f:
        args += ["--initial", "x'=0.3", "--initial", "th'=1"]
    if "--set" in f:
        for name, value in settings(f).items():
            args += ["--set", f"{name}={value}"]
    if "--sensitivity" in f:
        args += ["--sensitivity", "k"]
    if "variational" in f:
        args += ["--integrator", "variational", "--step", "0.0005"]
    if "backend" in f:
        args += ["--backend", "compiled"]
    return subprocess.run(args, capture_output=True, text=True, cwd=tmp_path)


def read_cli(tmp_path):
    with open(tmp_path / "run.csv") as stream:
        rows = list(csv.DictReader(stream))
    columns = {name: np.array([float(r[name]) for r in rows]) for name in rows[0]}
    events = []
    if (tmp_path / "run.events.csv").exists():
        with open(tmp_path / "run.events.csv") as stream:
            events = [(r["name"], float(r["t"])) for r in csv.DictReader(stream)]
    return columns, events


def run_python(f, tmp_path):
    path = tmp_path / "combination.toml"
    path.write_text(scene_text(f))
    scene = nhc.Scene.load(path, set=settings(f) if "--set" in f else None)
    kwargs = {}
    if "--input" in f:
        kwargs["inputs"] = lambda t, y: [0.5 + K * t, 0.0]
    if "--initial" in f:
        kwargs["initial"] = {"x'": 0.3, "th'": 1.0}
    if "--sensitivity" in f:
        kwargs["sensitivity"] = ["k"]
    if "variational" in f:
        kwargs.update(integrator="variational", step=0.0005)
    run = scene.build().simulate(**kwargs)
    columns = {name: np.asarray(run[name]) for name in run.columns}
    return columns, [(e.name, e.t) for e in run.events]


def check_against_reference(f, columns, events):
    ref, ref_events = reference(f)
    tol = 1e-4 if "variational" in f else 2e-5 if "contact slide" in f else 1e-6
    t = columns["t"]
    assert len(t) == len(ref), (t, ref[:, 0])
    assert np.max(np.abs(t - ref[:, 0])) < 1e-6
    for i, name in enumerate(["x", "x'", "th", "th'"], start=1):
        assert np.max(np.abs(columns[name] - ref[:, i])) < tol * max(1.0, np.max(np.abs(ref[:, i]))), name
    if "variational" not in f:
        assert [n for n, _ in events] == [n for n, _ in ref_events], (events, ref_events)
        for (_, a), (_, b) in zip(events, ref_events):
            assert abs(a - b) < 1e-6
    if "outputs" in f and "--sensitivity" not in f:  # a sensitivity run's columns: the states and d/dk
        ke = M / 2 * ref[:, 2] ** 2 + M * R * R / 4 * ref[:, 4] ** 2
        assert np.max(np.abs(columns["ke"] - ke)) < tol * max(1.0, np.max(ke))
    if "--sensitivity" in f:  # central differences of the motion by hand in k
        hk = 1e-4
        up, _ = reference(f, K + hk)
        down, _ = reference(f, K - hk)
        assert np.max(np.abs(columns["d(x)/d(k)"] - (up[:, 1] - down[:, 1]) / (2 * hk))) < 1e-6


@pytest.mark.parametrize("row,col,text", cells(), ids=lambda v: v if isinstance(v, str) and len(v) < 20 else None)
def test_pair(row, col, text, tmp_path):
    f = {row, col}
    assert text.startswith("works") or text.startswith("refused") or text.startswith("TODO"), text
    if text.startswith("TODO"):
        pytest.skip(text)
    python = "Python" in f
    if text.startswith("refused"):
        words = re.search(r"“(.*?)”", text).group(1)
        if python:
            with pytest.raises(nhc.SceneError, match=re.escape(words)):
                run_python(f, tmp_path)
        else:
            done = run_cli(f, tmp_path)
            assert done.returncode == 2 and words in done.stderr, done.stderr
            assert not (tmp_path / "run.csv").exists()
        return
    if python:
        columns, events = run_python(f, tmp_path)
    else:
        done = run_cli(f, tmp_path)
        assert done.returncode == 0, done.stderr
        columns, events = read_cli(tmp_path)
    check_against_reference(f, columns, events)


CYLINDER_TORQUE = scene_text({"controller", "contact stop"})


def test_a_python_controller_keeps_events_and_slip_detection(tmp_path):
    """controller=f (the held torque k t_k) on the cylinder whose contact stops at a slip: the
    friction demand 2 T/(3 r) exceeds mu m g at the first sample with k t_k > 1.5 mu m g r (1.7658),
    t = 1.8, where the held torque jumps; the stop event x' = V of a second scene at t = sqrt(3.6),
    between samples (x' = k t^2/(3 m r) under the torque k t sampled: by hand below)."""
    model = nhc.Scene.from_toml(CYLINDER_TORQUE).build()
    run = model.simulate(controller=lambda t, y, z: ([K * t, 0.0], z), period=H)
    ref, ref_events = reference({"controller", "contact stop"})
    assert [(e.name, round(e.t, 9)) for e in run.events] == [("floor.slip", 1.8)]
    assert [n for n, _ in ref_events] == ["floor.slip"] and abs(ref_events[0][1] - 1.8) < 1e-12
    assert np.max(np.abs(run["x"] - ref[:, 1])) < 1e-9 and abs(run.t[-1] - 1.8) < 1e-12
    events = nhc.Scene.from_toml(scene_text({"controller", "events"})).build()
    run = events.simulate(controller=lambda t, y, z: ([K * t, 0.0], z), period=H)
    ref, ref_events = reference({"controller", "events"})
    assert [e.name for e in run.events] == [n for n, _ in ref_events] == ["mark", "fast"]
    assert max(abs(e.t - t) for e, (_, t) in zip(run.events, ref_events)) < 1e-8
    assert abs(run.t[-1] - ref_events[-1][1]) < 1e-8 and run.t[-1] < T_END - 0.5


ROLLING_RATE = scene_text({"contact slide"}).replace("x = [0.0, 0.0]", "x = [0.0]").replace(
    "th = [0.0, 0.0]", "th = [0.0, 10.0]").replace('T = "k*t"', 'T = "0"')


def test_a_sliding_contact_starts_from_the_rolling_models_consistent_point(tmp_path):
    """x = [0.0], th = [0.0, 10.0] under x' - r*th', no torque: the rolling model solves x' = r th'
    = 3, and the cylinder rolls on at x = 3 t with no slip and no stick (as on_slip = "stop" does)."""
    path = tmp_path / "rate.toml"
    path.write_text(ROLLING_RATE)
    run = nhc.Scene.load(path).build().simulate()
    assert list(run.events) == []
    assert np.max(np.abs(run["x'"] - 3.0)) < 1e-12 and np.max(np.abs(run["x"] - 3.0 * run.t)) < 1e-10
    done = subprocess.run([nhc_command(), "simulate", str(path), "-o", str(tmp_path / "rate.csv")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    with open(tmp_path / "rate.csv") as stream:
        rows = list(csv.DictReader(stream))
    assert all(abs(float(r["x'"]) - 3.0) < 1e-12 and float(r["floor.state"]) == 1 for r in rows)
    assert (tmp_path / "rate.events.csv").read_text() == "name,t\n"


def test_no_side_file_beside_a_fifo(tmp_path):
    """-o a FIFO (a stream, written in place): the event table is not written beside it, a note says so."""
    path = tmp_path / "events.toml"
    path.write_text(scene_text({"events"}))
    fifo = tmp_path / "out.csv"
    os.mkfifo(fifo)
    reader = subprocess.Popen(["cat", str(fifo)], stdout=subprocess.PIPE, text=True)
    done = subprocess.run([nhc_command(), "simulate", str(path), "-o", str(fifo)], capture_output=True, text=True,
                          timeout=120)
    rows = reader.communicate(timeout=60)[0]
    assert done.returncode == 0, done.stderr
    assert rows.startswith("t,x,") and not (tmp_path / "out.events.csv").exists()
    assert "note: no file beside " + str(fifo) in done.stdout


REFERENCE_OSCILLATOR = """
name = "oscillator"
coordinates = ["x"]
lagrangian = "x'^2/2 - x^2/2"
[initial]
x = [1.0, 0.0]
[simulate]
t_end = 3.0
rtol = 1e-10
atol = 1e-12
[reference]
x = "cos(t)"
"""


def test_initial_values_from_outside_drop_the_reference_comparison(tmp_path):
    """--initial x=2 (initial= in Python): the motion is 2 cos t, not the scene's reference cos t;
    the comparison is dropped with a note instead of 'max reference error 1'."""
    path = tmp_path / "oscillator.toml"
    path.write_text(REFERENCE_OSCILLATOR)
    done = subprocess.run([nhc_command(), "simulate", str(path), "--initial", "x=2", "-o", str(tmp_path / "o.csv")],
                          capture_output=True, text=True)
    assert done.returncode == 0 and "max reference error" not in done.stdout, done.stdout
    assert "no reference error: the closed forms of [reference] start from the scene's own [initial]" in done.stdout
    with open(tmp_path / "o.csv") as stream:
        rows = list(csv.DictReader(stream))
    assert max(abs(float(r["x"]) - 2 * np.cos(float(r["t"]))) for r in rows) < 1e-8
    plain = subprocess.run([nhc_command(), "simulate", str(path)], capture_output=True, text=True)
    assert "max reference error" in plain.stdout
    run = nhc.Scene.load(path).build().simulate(initial={"x": 2.0})
    assert run.summary["reference_error"] is None and "initial= or t0=" in run.summary["reference_note"]
    assert np.max(np.abs(run["x"] - 2 * np.cos(run.t))) < 1e-8


VISUAL_CYLINDER = """
[visual]
wheel = { shape = "sphere", radius = "r", center = "[x, 0, r]" }
"""


def test_animate_goes_through_the_engine(tmp_path):
    """nhc animate: on_slip = "slide" (the launched cylinder slides, then rolls: the stick at
    v0/(3 mu g), docs/contacts.md eq. (6)), and with "stop" the same words and exit code as nhc
    simulate for given values that miss the rolling constraint (no page)."""
    text = scene_text({"contact slide"}).replace('T = "k*t"', 'T = "0"').replace("x = [0.0, 0.0]", "x = [0.0, 3.0]")
    path = tmp_path / "launched.toml"
    path.write_text(text + VISUAL_CYLINDER)
    done = subprocess.run([nhc_command(), "animate", str(path), "-o", str(tmp_path / "page")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    page = (tmp_path / "page" / "index.html").read_text()
    data = json.loads(re.search(r'\{"scene":.*?\]\}', page, flags=re.S).group(0))
    t = np.array(data["t"])
    x = np.array(data["visuals"][0]["position"])[0::3]
    v0, t_roll = 3.0, 3.0 / (3 * MU * G)
    closed = np.where(t < t_roll, v0 * t - MU * G * t**2 / 2,
                      v0 * t_roll - MU * G * t_roll**2 / 2 + 2 * v0 / 3 * (t - t_roll))
    assert len(t) == 27 and abs(t[6] - t_roll) < 1e-6 and np.max(np.abs(x - closed)) < 1e-5  # the stick a row too
    stopped = tmp_path / "stopped.toml"
    stopped.write_text(text.replace('on_slip = "slide"', 'on_slip = "stop"') + VISUAL_CYLINDER)
    done = subprocess.run([nhc_command(), "animate", str(stopped), "-o", str(tmp_path / "refused")],
                          capture_output=True, text=True)
    simulated = subprocess.run([nhc_command(), "simulate", str(stopped)], capture_output=True, text=True)
    assert done.returncode == simulated.returncode == 3, done.stderr
    assert "violate hidden constraint f1 at t0 = 0" in done.stderr
    assert done.stderr.splitlines()[0] == simulated.stderr.splitlines()[0]
    assert not (tmp_path / "refused").exists()
