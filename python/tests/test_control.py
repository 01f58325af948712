"""Linearization for control and parameter studies, each against an independent path:
a SymPy model of the two-wheeled pendulum written here, `nhc simulate --set`, the compile cache's
contents."""
import hashlib
import os
import pathlib
import subprocess

import numpy as np
import pytest

import nhc

HERE = pathlib.Path(__file__).resolve().parent
PENDULUM = HERE / "scenes" / "two_wheel_pendulum.toml"
STATES = ["x", "x'", "th", "th'", "psi", "psi'"]


def nhc_command():
    """The nhc program of the build (NHC_EXECUTABLE, set by ctest)."""
    program = os.environ.get("NHC_EXECUTABLE")
    if not program:
        pytest.skip("NHC_EXECUTABLE is not set (ctest sets it)")
    return program


def sympy_linearization(p):
    """A and B over (x, v, th, th', psi, psi') at upright rest, from the Lagrangian of the scene's
    header comment and Kane-style projection onto the generalized speeds u = (v, th', psi'), with
    x' = v cos psi, y' = v sin psi, phL' = (v - d psi')/r, phR' = (v + d psi')/r: the
    Lagrange-d'Alembert equations are S^T (d/dt dL/dq' - dL/dq - Q) = 0, q' = S(q) u."""
    sp = pytest.importorskip("sympy")
    t = sp.symbols("t")
    names = ["x", "y", "psi", "th", "phL", "phR"]
    q = [sp.Function(n)(t) for n in names]
    x, y, psi, th, phL, phR = q
    mb, l, Ib1, Ib2, Ib3, mw, r, d, g = (p[k] for k in ["mb", "l", "Ib1", "Ib2", "Ib3", "mw", "r", "d", "g"])
    Ja, Jd = mw * r**2 / 2, mw * r**2 / 4
    TL, TR = sp.symbols("TL TR")
    # The body's centre of mass and angular velocity, from the frames (not from the scene's formulas).
    ef = sp.Matrix([sp.cos(psi), sp.sin(psi), 0])
    el = sp.Matrix([-sp.sin(psi), sp.cos(psi), 0])
    ez = sp.Matrix([0, 0, 1])
    c = sp.Matrix([x, y, r])
    cb = c + l * (sp.sin(th) * ef + sp.cos(th) * ez)
    b1, b2, b3 = sp.cos(th) * ef - sp.sin(th) * ez, el, sp.sin(th) * ef + sp.cos(th) * ez
    w = psi.diff(t) * ez + th.diff(t) * el
    T_body = mb / 2 * cb.diff(t).dot(cb.diff(t)) + (Ib1 * w.dot(b1)**2 + Ib2 * w.dot(b2)**2 + Ib3 * w.dot(b3)**2) / 2
    T_wheels = 0
    for side, ph in ((1, phL), (-1, phR)):
        cw = c + side * d * el
        T_wheels += mw / 2 * cw.diff(t).dot(cw.diff(t)) + (Jd * psi.diff(t)**2 + Ja * ph.diff(t)**2) / 2
    L = T_body + T_wheels - mb * g * (r + l * sp.cos(th))
    Q = [0, 0, 0, -TL - TR, TL, TR]
    E = [sp.diff(L.diff(qi.diff(t)), t) - L.diff(qi) - Qi for qi, Qi in zip(q, Q)]
    v, om, ps, vd, omd, psd = sp.symbols("v om ps vd omd psd")  # u = (v, th', psi') and u'
    S = sp.Matrix([[sp.cos(psi), 0, 0], [sp.sin(psi), 0, 0], [0, 0, 1], [0, 1, 0],
                   [1 / r, 0, -d / r], [1 / r, 0, d / r]])
    u, ud = sp.Matrix([v, om, ps]), sp.Matrix([vd, omd, psd])
    qd = S * u
    qdd = S.diff(t).subs({psi.diff(t): ps}) * u + S * ud
    subs = {}
    for k, qi in enumerate(q):
        subs[qi.diff(t, 2)] = qdd[k]
    for k, qi in enumerate(q):
        subs[qi.diff(t)] = qd[k]
    symbols = sp.symbols("X Y PSI TH PHL PHR")
    E = [sp.expand(e.subs(subs)).subs(dict(zip(q, symbols))) for e in E]
    projected = S.subs(dict(zip(q, symbols))).T * sp.Matrix(E)
    X, Y, PSI, TH = symbols[:4]
    state = [X, v, TH, om, PSI, ps]
    point = {s: 0 for s in list(symbols) + [v, om, ps, vd, omd, psd, TL, TR]}
    M = np.array(projected.jacobian(ud).subs(point), dtype=float)
    J = np.array(projected.jacobian(state).subs(point), dtype=float)
    F = np.array(projected.jacobian([TL, TR]).subs(point), dtype=float)
    accelerations = -np.linalg.solve(M, J)  # rows v', th'', psi''
    inputs = -np.linalg.solve(M, F)
    A = np.zeros((6, 6))
    B = np.zeros((6, 2))
    A[0, 1] = A[2, 3] = A[4, 5] = 1.0  # x' = v cos psi = v to first order at rest; th' and psi'
    for row, k in zip((1, 3, 5), range(3)):
        A[row] = accelerations[k]
        B[row] = inputs[k]
    return A, B


def test_keep_x_gives_six_states_whose_eigenvalues_match_sympy():
    scene = nhc.Scene.load(PENDULUM)
    parameters = scene.parameters
    A_ref, B_ref = sympy_linearization(parameters)

    free = scene.linearize(keep=["x"])
    assert free.kept == ["x"] and "x" not in free.cyclic
    assert len(free.states) == 6 and "x" in free.states
    reference = np.sort_complex(np.linalg.eigvals(A_ref))
    found = np.sort_complex(free.eigenvalues)
    assert np.max(np.abs(found - reference)) < 1e-9 * np.max(np.abs(reference))
    # Two double zeros (x and psi: Jordan blocks) and the pitch pair +-sqrt(...).
    assert free.zero_eigenvalues == 4
    assert np.max(np.abs(free.A @ free.A @ free.A)) > 0  # not nilpotent: the pitch pair is there

    chosen = scene.linearize(keep=["x"], states=STATES)
    assert chosen.states == STATES and chosen.inputs == ["TL", "TR"]
    assert np.max(np.abs(chosen.A - A_ref)) < 1e-10 * np.max(np.abs(A_ref))
    assert np.max(np.abs(chosen.B - B_ref)) < 1e-10 * np.max(np.abs(B_ref))
    # x's Jordan block: A e_x = 0 and A e_x' = e_x.
    assert np.all(chosen.A[:, 0] == 0) and chosen.A[0, 1] == 1.0

    without = scene.linearize()
    assert "x" in without.cyclic and len(without.states) == 5


def test_the_wheeled_pendulum_example_linearizes_as_the_sympy_model(source):
    # The example scene against the SymPy model written here, upright at rest.
    path = source / "examples" / "wheeled_pendulum.toml"
    scene = nhc.Scene.load(path)
    A_ref, B_ref = sympy_linearization(scene.parameters)
    lin = scene.linearize(at={"th": 0.0, "th'": 0.0}, keep=["x"], states=STATES)
    assert lin.states == STATES and lin.zero_eigenvalues == 4
    assert np.max(np.abs(lin.A - A_ref)) < 1e-10 * np.max(np.abs(A_ref))
    assert np.max(np.abs(lin.B - B_ref)) < 1e-10 * np.max(np.abs(B_ref))


def test_keep_and_states_refusals():
    scene = nhc.Scene.load(PENDULUM)
    with pytest.raises(nhc.SceneError, match="--keep z: not a coordinate"):
        scene.linearize(keep=["z"])
    with pytest.raises(nhc.SceneError, match=r"--states x: .*cyclic and removed: keep it with --keep x"):
        scene.linearize(states=["x"])
    with pytest.raises(nhc.SceneError, match="--states names 2 states; the linearization has 6"):
        scene.linearize(keep=["x"], states=["x", "th"])


def test_linearize_text_names_rows_and_columns():
    out = subprocess.run([nhc_command(), "linearize", str(PENDULUM), "--keep", "x", "--states", ",".join(STATES)],
                         capture_output=True, text=True, check=True).stdout
    lines = out.splitlines()
    a = next(k for k, line in enumerate(lines) if line.strip().startswith("A ("))
    assert lines[a + 1].split() == STATES
    assert [lines[a + 2 + k].split()[0] for k in range(6)] == STATES
    assert lines[a + 3].split()[1:] == ["0", "0", "-7.936179775", "0", "0", "0"]  # x' row: d(δx')/dt
    b = next(k for k, line in enumerate(lines) if line.strip().startswith("B ("))
    assert lines[b + 1].split() == ["TL", "TR"]
    assert [lines[b + 2 + k].split()[0] for k in range(6)] == STATES
    assert "cyclic coordinates kept as states: x" in out
    refused = subprocess.run([nhc_command(), "linearize", str(PENDULUM), "--keep", "x,z"], capture_output=True, text=True)
    assert refused.returncode == 2 and "--keep z: not a coordinate" in refused.stderr and refused.stdout == ""


def test_a_parameter_study_compiles_once_and_matches_simulate_set(source, tmp_path, monkeypatch):
    # A fresh compile cache: the first build compiles, the other 19 values find its library.
    monkeypatch.setenv("NHC_CACHE_DIR", str(tmp_path / "cache"))
    path = source / "examples" / "rolling_disk.toml"
    values = np.linspace(0.3, 0.7, 20)
    runs = [nhc.Scene.load(path, set={"r": float(values[0])}).build().simulate(t_end=0.5, outputs=10)]
    libraries = [f for f in (tmp_path / "cache").rglob("*.so")]
    assert len(libraries) == 1, libraries
    # The cache replaces a library by renaming a new file over it (a new inode) and marks a use by
    # its time (the size cap's eviction order): the same inode and bytes mean nothing was compiled.
    compiled = (libraries[0].stat().st_ino, hashlib.sha256(libraries[0].read_bytes()).hexdigest())
    for r in values[1:]:
        runs.append(nhc.Scene.load(path, set={"r": float(r)}).build().simulate(t_end=0.5, outputs=10))
    # The other 19 values compiled nothing: the one library, untouched since the first build.
    assert [f for f in (tmp_path / "cache").rglob("*.so")] == libraries
    assert (libraries[0].stat().st_ino, hashlib.sha256(libraries[0].read_bytes()).hexdigest()) == compiled
    assert runs[0].summary["compile_seconds"] > 0
    assert len({float(run["x"][-1]) for run in runs}) == 20  # 20 different motions
    # The same numbers as the command line's --set (CSV of 17 significant digits).
    for k in (0, 5, 10, 15, 19):  # spread over the study (each a command-line run of its own)
        csv = tmp_path / f"set{k}.csv"
        subprocess.run([nhc_command(), "simulate", str(path), "--set", f"r={values[k]!r}", "--t-end", "0.5",
                        "--outputs", "10", "-o", str(csv)], capture_output=True, check=True)
        header = csv.read_text().splitlines()[0].split(",")
        table = np.loadtxt(csv, delimiter=",", skiprows=1)
        for c, name in enumerate(header):
            if name in runs[k]:
                assert np.max(np.abs(table[:, c] - runs[k][name])) <= 1e-12 * (1 + np.max(np.abs(table[:, c]))), name
    # The set= values are the run's: [initial] written through r follows, the model reports them.
    model = nhc.Scene.load(path, set={"r": 0.45}).build()
    assert model.parameters["r"] == 0.45


def reduced_velocity(model, t, sample_y, s, u, p):
    """d/dt of s = (x, x', th, th', psi, psi') of the two-wheeled pendulum from the compiled residual
    alone: the velocities the constraints fix written here by hand (y' = x' tan psi, the wheel
    rates), then F(t, y, y', u) = 0 solved by Newton for the derivatives of the differential states
    and the algebraic states (the multipliers). An independent path to A(t) and B(t)."""
    names = model.state_names
    index = {name: k for k, name in enumerate(names)}
    differential = model._model.differential
    y = np.array(sample_y, dtype=float)
    x, xd, th, thd, psi, psid = s
    yd = xd * np.tan(psi)
    forward = xd * np.cos(psi) + yd * np.sin(psi)
    for name, value in (("x", x), ("x'", xd), ("th", th), ("th'", thd), ("psi", psi), ("psi'", psid), ("y'", yd),
                        ("phL'", (forward - p["d"] * psid) / p["r"]), ("phR'", (forward + p["d"] * psid) / p["r"])):
        y[index[name]] = value
    yp = np.zeros(len(y))
    unknowns = [("yp", k) for k in range(len(y)) if differential[k]] + [("y", k) for k in range(len(y)) if not differential[k]]
    for _ in range(30):
        F = model.residual(t, y, yp, u)
        dFdy = model.jacobian(t, y, yp, 0.0)
        dFdyp = model.jacobian(t, y, yp, 1.0) - dFdy
        K = np.column_stack([dFdyp[:, k] if kind == "yp" else dFdy[:, k] for kind, k in unknowns])
        step = np.linalg.solve(K, -F)
        for (kind, k), d in zip(unknowns, step):
            if kind == "yp":
                yp[k] += d
            else:
                y[k] += d
        if np.max(np.abs(step)) < 1e-15:
            break
    return np.array([yp[index[name]] for name in STATES])


def test_linearize_along_and_input_jacobian_match_finite_differences():
    scene = nhc.Scene.load(PENDULUM)
    model = scene.build()
    u_of = lambda t, y: [0.2 * np.cos(3 * t), -0.1]  # turning while it falls
    run = model.simulate(t_end=0.4, outputs=4, inputs=u_of, rtol=1e-10, atol=1e-12)
    along = model.linearize_along(run, inputs=u_of, keep=["x"], states=STATES)
    assert along.A.shape == (5, 6, 6) and along.B.shape == (5, 6, 2) and along.states == STATES
    p = scene.parameters
    names = model.state_names
    for r in (1, 4):
        t = run.t[r]
        sample = np.array([run[name][r] for name in names])
        s0 = np.array([run[name][r] for name in STATES])
        u0 = np.array(u_of(t, sample))
        h = 1e-6
        A_fd = np.column_stack([(reduced_velocity(model, t, sample, s0 + h * e, u0, p) -
                                 reduced_velocity(model, t, sample, s0 - h * e, u0, p)) / (2 * h) for e in np.eye(6)])
        B_fd = np.column_stack([(reduced_velocity(model, t, sample, s0, u0 + h * e, p) -
                                 reduced_velocity(model, t, sample, s0, u0 - h * e, p)) / (2 * h) for e in np.eye(2)])
        assert np.max(np.abs(along.A[r] - A_fd)) < 1e-6 * np.max(np.abs(A_fd)), (along.A[r], A_fd)
        assert np.max(np.abs(along.B[r] - B_fd)) < 1e-6 * np.max(np.abs(B_fd)), (along.B[r], B_fd)
        # dF/du against central differences of the compiled residual in u.
        yp = np.array([run[name + "'"][r] if name + "'" in run else 0.0 for name in names])
        J_fd = np.column_stack([(model.residual(t, sample, yp, u0 + h * e) - model.residual(t, sample, yp, u0 - h * e)) /
                                (2 * h) for e in np.eye(2)])
        J = model.input_jacobian(t, sample, yp, u0)
        assert J.shape == (len(names), 2)
        assert np.max(np.abs(J - J_fd)) < 1e-8
        assert np.max(np.abs(J)) == 1.0  # the torques enter R_th, R_phL, R_phR with unit coefficients
    # Along a motion that is not steady the pitch row depends on the state: A(t) is not constant.
    assert np.max(np.abs(along.A[4] - along.A[0])) > 1e-3


def test_run_has_the_scenes_outputs_as_the_command_line_writes_them(tmp_path):
    # A pendulum with the bob's height and the tension-like quantity g cos th + l th'^2 as
    # [outputs]: the closed forms evaluated on the run's own columns, and nhc simulate's CSV.
    text = """
name = "pendulum_outputs"
coordinates = ["th"]
lagrangian = "l^2*th'^2/2 + g*l*cos(th)"
[parameters]
g = 9.81
l = 0.7
[outputs]
height = "-l*cos(th)"
pull = "g*cos(th) + l*th'^2"
[initial]
th = [0.4, 0.0]
[simulate]
t_end = 1.0
outputs = 20
"""
    path = tmp_path / "pendulum_outputs.toml"
    path.write_text(text)
    run = nhc.Scene.load(path, set={"l": 0.5}).build().simulate()
    assert run.columns[-2:] == ["height", "pull"]
    assert np.max(np.abs(run["height"] + 0.5 * np.cos(run["th"]))) < 1e-15
    assert np.max(np.abs(run["pull"] - (9.81 * np.cos(run["th"]) + 0.5 * run["th'"]**2))) < 1e-13
    csv = tmp_path / "run.csv"
    subprocess.run([nhc_command(), "simulate", str(path), "--set", "l=0.5", "-o", str(csv)], capture_output=True, check=True)
    header = csv.read_text().splitlines()[0].split(",")
    assert header == run.columns
    assert np.max(np.abs(np.loadtxt(csv, delimiter=",", skiprows=1) - run.to_numpy())) < 1e-12


def disk_velocity(model, s, p):
    """d/dt of s = (th, th', ph, ph', ps') of the rolling disk from the compiled residual alone: the
    rolling constraints written here (x' = r ps' cos ph, y' = r ps' sin ph), then F = 0 solved by
    Newton for the derivatives of the differential states and for the multipliers."""
    names = model.state_names
    index = {name: k for k, name in enumerate(names)}
    differential = model._model.differential
    y = np.zeros(len(names))
    th, thd, ph, phd, psd = s
    for name, value in (("th", th), ("th'", thd), ("ph", ph), ("ph'", phd), ("ps'", psd),
                        ("x'", p["r"] * psd * np.cos(ph)), ("y'", p["r"] * psd * np.sin(ph))):
        y[index[name]] = value
    yp = np.zeros(len(names))
    unknowns = [("yp", k) for k in range(len(y)) if differential[k]] + [("y", k) for k in range(len(y)) if not differential[k]]
    for _ in range(30):
        F = model.residual(0.0, y, yp)
        dFdy = model.jacobian(0.0, y, yp, 0.0)
        dFdyp = model.jacobian(0.0, y, yp, 1.0) - dFdy
        K = np.column_stack([dFdyp[:, k] if kind == "yp" else dFdy[:, k] for kind, k in unknowns])
        step = np.linalg.solve(K, -F)
        for (kind, k), d in zip(unknowns, step):
            if kind == "yp":
                yp[k] += d
            else:
                y[k] += d
        if np.max(np.abs(step)) < 1e-15:
            break
    return np.array([yp[index[name]] for name in ["th", "th'", "ph", "ph'", "ps'"]])


def test_a_steady_turn_of_the_rolling_disk_linearizes_in_the_turning_frame(source):
    # A steady circle: lean 0.3, heading rate 2, and the spin rate at which th'' = 0 (found by the
    # secant method on the analysis' th''). ph is not cyclic (the rolling constraints contain it):
    # without --turn the point is refused as not stationary.
    path = source / "tests" / "linearize" / "scenes" / "rolling_disk.toml"
    text = path.read_text()
    def lean_acceleration(spin):
        changed = text.replace("th = [0.0, 0.0]", "th = [0.3, 0.0]").replace("ph = [0.0, 0.0]", "ph = [0.0, 2.0]")
        return nhc.Scene.from_toml(changed.replace("ps = [0.0, 6.0]", f"ps = [0.0, {spin!r}]")).analyze("chetaev").initial_point["th''"]
    a, b = 1.0, 10.0
    fa, fb = lean_acceleration(a), lean_acceleration(b)
    for _ in range(60):
        a, fa, b = b, fb, b - fb * (b - a) / (fb - fa)
        fb = lean_acceleration(b)
        if abs(fb) < 1e-13:
            break
    scene = nhc.Scene.load(path)
    at = {"th": 0.3, "ph'": 2.0, "ps'": b}
    with pytest.raises(nhc.MathError, match="the operating point is not stationary"):
        scene.linearize(at=at)
    lin = scene.linearize(at=at, turn="ph:x,y")
    assert lin.turn_rate == 2.0 and lin.states == ["th", "th'", "ph", "ph'", "ps'"]
    model = scene.build()
    s0 = np.array([0.3, 0.0, 0.0, 2.0, b])
    # Stationary in the turning frame: f(s0) = omega e_ph.
    assert np.max(np.abs(disk_velocity(model, s0, scene.parameters) - np.array([0, 0, 2.0, 0, 0]))) < 1e-12
    h = 1e-6
    A_fd = np.column_stack([(disk_velocity(model, s0 + h * e, scene.parameters) -
                             disk_velocity(model, s0 - h * e, scene.parameters)) / (2 * h) for e in np.eye(5)])
    assert np.max(np.abs(lin.A - A_fd)) < 1e-7 * np.max(np.abs(A_fd)), (lin.A, A_fd)
    # Steady circles are stable here: a pair on the imaginary axis, no eigenvalue to the right.
    assert max(lin.eigenvalues.real) < 1e-5
    assert np.max(np.abs(lin.eigenvalues.imag)) > 0.1
    # The turn must be a symmetry: th and x do not turn together.
    with pytest.raises(nhc.SceneError, match="keep both or neither"):
        scene.linearize(at=at, turn="ph:x,th")


DRIVEN = """
name = "driven_oscillator"
coordinates = ["x"]
lagrangian = "x'^2/2 - k*x^2/2"
[parameters]
k = 4.0
a = 0.5
w = 3.0
[inputs]
u = "a*sin(w*t)"
[forces]
x = "u"
[initial]
x = [0.2, 0.0]
"""


def test_sensitivities_with_inputs_follow_their_default_signals(tmp_path):
    # x'' = -k x + a sin(w t): the sensitivities by k (through the equation), a and w (only
    # through the input's default signal) against central differences of runs.
    names = ["k", "a", "w"]
    times = np.linspace(0.0, 2.0, 11)
    options = dict(output_times=times, rtol=1e-11, atol=1e-13)
    sens = nhc.Scene.from_toml(DRIVEN).build().simulate(sensitivity=names, **options)
    base = {"k": 4.0, "a": 0.5, "w": 3.0}
    for name in names:
        h = 1e-5 * base[name]
        up = nhc.Scene.from_toml(DRIVEN, set={name: base[name] + h}).build().simulate(**options)
        down = nhc.Scene.from_toml(DRIVEN, set={name: base[name] - h}).build().simulate(**options)
        for state in ("x", "x'"):
            fd = (up[state] - down[state]) / (2 * h)
            column = sens[f"d({state})/d({name})"]
            assert np.max(np.abs(column - fd)) < 1e-6 * (1 + np.max(np.abs(fd))), (name, state, column, fd)
            assert np.max(np.abs(column)) > 1e-2  # every one of them moves the motion
    # The same columns from the command line; an --input replacing the signal is refused there.
    path = tmp_path / "driven.toml"
    path.write_text(DRIVEN)
    csv = tmp_path / "sens.csv"
    subprocess.run([nhc_command(), "simulate", str(path), "--sensitivity", "k,a,w", "--output-times",
                    ",".join(repr(t) for t in times), "--rtol", "1e-11", "--atol", "1e-13", "-o", str(csv)],
                   capture_output=True, check=True)
    header = csv.read_text().splitlines()[0].split(",")
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    for c, name in enumerate(header):
        assert np.max(np.abs(table[:, c] - sens[name])) < 1e-12 * (1 + np.max(np.abs(table[:, c]))), name
    refused = subprocess.run([nhc_command(), "simulate", str(path), "--sensitivity", "a", "--input", "u=0"],
                             capture_output=True, text=True)
    assert refused.returncode == 2 and "does not go with --input" in refused.stderr
    with pytest.raises(nhc.SceneError, match="default input signals"):
        nhc.Scene.from_toml(DRIVEN).build().simulate(sensitivity=["a"], inputs=lambda t, y: [0.0])


def test_the_scenes_simulate_model_is_the_default_model():
    # As on the command line (default_model): [simulate] model, else chetaev.
    text = OSCILLATOR_MODELS + '[simulate]\nmodel = "vakonomic"\n'
    scene = nhc.Scene.from_toml(text)
    assert scene.default_model == "vakonomic"
    assert scene.build().name == "vakonomic" and scene.derive().model == "vakonomic"
    assert scene.analyze().model == "vakonomic"
    assert nhc.Scene.from_toml(OSCILLATOR_MODELS).build().name == "chetaev"


OSCILLATOR_MODELS = """
name = "oscillator_models"
coordinates = ["x"]
lagrangian = "x'^2/2 - x^2/2"
[initial]
x = [1.0, 0.0]
"""


def csv_table(path):
    """A CSV nhc wrote: {column: array}."""
    header = path.read_text().splitlines()[0].split(",")
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    return {name: table[:, c] for c, name in enumerate(header)}


def test_initial_values_from_outside_equal_the_same_values_written_in_the_scene(source, tmp_path):
    # The wheeled pendulum started at t0 = 0.5 from a tilt with a pitch rate and a yaw rate: once
    # written into the scene's [initial], once from --initial, once from Python's initial=/t0=.
    path = source / "examples" / "wheeled_pendulum.toml"
    text = path.read_text()
    written = (text.replace("t0 = 0.0", "t0 = 0.5").replace("th = [0.05, 0.0]", "th = [0.12, -0.3]")
               .replace("psi = [0.0, 0.0]", "psi = [0.0, 0.4]").replace("phL = [0.0, 0.0]", "phL = [0.0, -0.6]")
               .replace("phR = [0.0, 0.0]", "phR = [0.0, 0.6]"))  # a turn on the spot: r (phR' - phL') / 2d = psi'

    assert written != text
    scene = tmp_path / "written.toml"
    scene.write_text(written)
    flags = ["--t-end", "1.2", "--outputs", "20"]
    subprocess.run([nhc_command(), "simulate", str(scene), *flags, "-o", str(tmp_path / "written.csv")],
                   capture_output=True, check=True)
    subprocess.run([nhc_command(), "simulate", str(path), *flags, "--initial", "t0=0.5", "--initial", "th=0.12",
                    "--initial", "th'=-0.3", "--initial", "psi'=0.4", "--initial", "phL'=-0.6", "--initial", "phR'=0.6", "-o", str(tmp_path / "flags.csv")],
                   capture_output=True, check=True)
    a, b = csv_table(tmp_path / "written.csv"), csv_table(tmp_path / "flags.csv")
    assert a["t"][0] == 0.5 and abs(a["psi"][-1]) > 0.1  # the run starts at t0 and turns
    for name in a:
        assert np.array_equal(a[name], b[name]), name
    run = nhc.Scene.load(path).build().simulate(t_end=1.2, outputs=20, t0=0.5,
                                                initial={"th": 0.12, "th'": -0.3, "psi'": 0.4,
                                                         "phL'": -0.6, "phR'": 0.6})
    for name in a:
        if name in run:
            assert np.max(np.abs(a[name] - run[name])) <= 1e-12 * (1 + np.max(np.abs(a[name]))), name


def test_initial_values_from_outside_are_checked(source):
    path = source / "examples" / "wheeled_pendulum.toml"
    for flag, words in (("z=1", "neither t0, a coordinate nor a multiplier"), ("th=inf", "--initial"),
                        ("x''=1", "x' is not given")):
        refused = subprocess.run([nhc_command(), "simulate", str(path), "--initial", flag],
                                 capture_output=True, text=True)
        assert refused.returncode == 2 and words in refused.stderr and "--initial" in refused.stderr, refused.stderr
    with pytest.raises(nhc.SceneError, match="neither t0"):
        nhc.Scene.load(path).build().simulate(initial={"z": 1.0})


LAW_L = "0.7*psi + 11*th + 2.4*th' - 0.01*phL' + 0.33*phR'"
LAW_R = "-0.7*psi + 11*th + 2.4*th' + 0.33*phL' - 0.01*phR'"


def test_a_state_law_from_the_scene_from_input_and_from_python_agree(source, tmp_path):
    # An LQR law (tests/scene/wheeled_pendulum_sympy.py) closing the wheeled pendulum from a 0.3 rad
    # tilt: written in [inputs], given as --input TL=..., and computed by a Python inputs= callback.
    path = source / "examples" / "wheeled_pendulum.toml"
    text = path.read_text().replace("th = [0.05, 0.0]", "th = [0.3, 0.0]")
    closed = tmp_path / "closed.toml"
    closed.write_text(text.replace('TL = "0"', f'TL = "{LAW_L}"').replace('TR = "0"', f'TR = "{LAW_R}"'))
    flags = ["--t-end", "2", "--outputs", "40", "--rtol", "1e-12", "--atol", "1e-13"]
    subprocess.run([nhc_command(), "simulate", str(closed), *flags, "-o", str(tmp_path / "scene.csv")],
                   capture_output=True, check=True)
    subprocess.run([nhc_command(), "simulate", str(path), *flags, "--initial", "th=0.3", "--input", f"TL={LAW_L}",
                    "--input", f"TR={LAW_R}", "-o", str(tmp_path / "flag.csv")], capture_output=True, check=True)
    a, b = csv_table(tmp_path / "scene.csv"), csv_table(tmp_path / "flag.csv")
    assert abs(a["th"][-1]) < 0.01  # the law holds the pendulum up
    for name in a:  # the input:TL/TR columns too: each holds the torque its law applies
        assert np.max(np.abs(a[name] - b[name])) <= 1e-9, name
    model = nhc.Scene.load(path).build()
    k = {name: i for i, name in enumerate(model.state_names)}

    def law(t, y):
        psi, th, dth, dL, dR = y[k["psi"]], y[k["th"]], y[k["th'"]], y[k["phL'"]], y[k["phR'"]]
        return [0.7 * psi + 11 * th + 2.4 * dth - 0.01 * dL + 0.33 * dR,
                -0.7 * psi + 11 * th + 2.4 * dth + 0.33 * dL - 0.01 * dR]

    run = model.simulate(t_end=2, outputs=40, rtol=1e-12, atol=1e-13, initial={"th": 0.3}, inputs=law)
    worst = max(float(np.max(np.abs(a[name] - run[name]))) for name in [*model.state_names, "input:TL", "input:TR"])
    assert worst <= 1e-9, worst
    # A law of an acceleration from --input is an algebraic loop, refused naming the flag.
    refused = subprocess.run([nhc_command(), "simulate", str(path), "--input", "TL=3*th''"],
                             capture_output=True, text=True)
    assert refused.returncode == 2 and "algebraic loop" in refused.stderr and "--input" in refused.stderr



def test_a_laws_input_column_holds_the_value_the_law_applies(source):
    # A law in [inputs] is compiled into the equations in place of its input: the run's input:NAME
    # column is the law at each row's own state (a signal of 0 before), directly and through a
    # definition, with IDA and with the variational integrator.
    text = (source / "examples" / "wheeled_pendulum.toml").read_text()
    text = text.replace("[definitions]\n", "[definitions]\ntilt = \"11*th + 2.4*th'\"\n", 1)
    text = text.replace('TL = "0"', 'TL = "-10*th"').replace('TR = "0"', 'TR = "tilt - 0.01*phL\'"')
    model = nhc.Scene.from_toml(text).build()
    for options in ({}, {"integrator": "variational", "step": 0.01}, {"sensitivity": ["l"]}):
        run = model.simulate(t_end=0.5, outputs=20, **options)
        TL, TR = -10 * run["th"], 11 * run["th"] + 2.4 * run["th'"] - 0.01 * run["phL'"]
        assert np.max(np.abs(run["input:TL"] - TL)) <= 1e-12 * (1 + np.max(np.abs(TL))), options
        assert np.max(np.abs(run["input:TR"] - TR)) <= 1e-12 * (1 + np.max(np.abs(TR))), options
        assert np.max(np.abs(TL)) > 0.01 and np.max(np.abs(TR)) > 0.01  # the laws moved

def zero_order_hold(A, B, h):
    """Ad, Bd of x' = A x + B u with u held over h: the exponential of [[A, B], [0, 0]] h (Taylor
    series after scaling by 2^-s, then squaring)."""
    n, m = B.shape
    G = np.zeros((n + m, n + m))
    G[:n, :n], G[:n, n:] = A * h, B * h
    s = max(0, int(np.ceil(np.log2(max(np.linalg.norm(G, 1), 1e-300)))) + 4)
    G = G / 2**s
    E, term = np.eye(n + m), np.eye(n + m)
    for k in range(1, 20):
        term = term @ G / k
        E = E + term
    for _ in range(s):
        E = E @ E
    return E[:n, :n], E[:n, n:]


def discrete_lqr(Ad, Bd, Q, R):
    """The gain K of u = -K x minimizing sum x'Qx + u'Ru: the Riccati difference equation iterated to its fixed point."""
    P = Q.copy()
    for _ in range(20000):
        K = np.linalg.solve(R + Bd.T @ P @ Bd, Bd.T @ P @ Ad)
        after = Q + Ad.T @ P @ (Ad - Bd @ K)
        if np.max(np.abs(after - P)) < 1e-12 * np.max(np.abs(P)):
            break
        P = after
    return K


def test_a_sampled_lqr_with_integral_action_matches_the_discrete_linear_model(source):
    # The wheeled pendulum's pitch and forward motion (equal torques TL = TR = u), linearized by the
    # SymPy model above, held over h = 0.01 s (100 Hz) and closed by a discrete LQR with an
    # integrator of x; nhc's nonlinear run under simulate(controller=, period=) and under the
    # scene's [controller] (examples/wheeled_pendulum_discrete.toml, whose gains are these) against
    # the discrete recursion of the linear model, whose difference shrinks as the tilt cubed (the
    # nonlinear terms are of third order in th at this symmetric operating point).
    path = source / "examples" / "wheeled_pendulum.toml"
    model = nhc.Scene.load(path).build()
    A6, B6 = sympy_linearization(nhc.Scene.load(path).parameters)
    A, B = A6[:4, :4], (B6[:4, 0] + B6[:4, 1]).reshape(4, 1)  # (x, v, th, th'), u = TL = TR
    h = 0.01
    Ad, Bd = zero_order_hold(A, B, h)
    Aa = np.zeros((5, 5))  # z_{k+1} = z_k + h x_k: the integral of the position error
    Aa[:4, :4], Aa[4, 0], Aa[4, 4] = Ad, h, 1.0
    Ba = np.vstack([Bd, [[0.0]]])
    K = discrete_lqr(Aa, Ba, np.diag([10.0, 1.0, 10.0, 1.0, 1.0]), np.eye(1))
    # The scene's gains are these (its header says how they were computed).
    discrete = nhc.Scene.load(source / "examples" / "wheeled_pendulum_discrete.toml")
    written = np.array([[discrete.parameters[f"k{j}"] for j in range(1, 6)]])
    assert np.max(np.abs(written - K)) < 1e-9 * np.max(np.abs(K)), (written, K)
    scene_model = discrete.build()
    k = {n: i for i, n in enumerate(model.state_names)}
    steps = 150

    def run_from(tilt, scene=False):
        times = []

        def controller(t, y, z):
            times.append(t)
            s = np.array([y[k["x"]], y[k["x'"]], y[k["th"]], y[k["th'"]], z])
            u = float(-(K @ s)[0])
            return [u, u], z + h * y[k["x"]]

        options = dict(t_end=steps * h, initial={"th": tilt}, rtol=1e-11, atol=1e-13)
        if scene:
            run = scene_model.simulate(**options)
        else:
            run = model.simulate(controller=controller, period=h, controller_state=0.0, **options)
        s = np.array([0.0, 0.0, tilt, 0.0, 0.0])
        linear = [s[:4]]
        for _ in range(steps):
            s = (Aa - Ba @ K) @ s
            linear.append(s[:4])
        mine = np.column_stack([run["x"], run["x'"], run["th"], run["th'"]])
        return run, times, float(np.max(np.abs(mine - np.array(linear))))

    run, times, small = run_from(0.01)
    # The controller ran at the samples only (the last one too), exactly at k h, and the rows are
    # those samples.
    assert len(times) == steps + 1 and times == [j * h for j in range(steps + 1)]
    assert np.array_equal(run.t, np.array([j * h for j in range(steps + 1)]))
    assert run.summary["controller_calls"] == steps + 1
    assert abs(run["th"][-1]) < 0.2 * 0.01  # the loop brings the pendulum up
    _, _, large = run_from(0.02)
    print(f"largest difference to the discrete linear model: {small:.3e} (tilt 0.01), {large:.3e} (tilt 0.02)")
    assert small < 10 * 0.01**3  # the size of the nonlinear terms (cubic in the tilt, coefficients ~ g/l)
    assert 5 < large / small < 11  # third order in the tilt
    # The scene's [controller] the same way.
    scene_run, _, scene_small = run_from(0.01, scene=True)
    _, _, scene_large = run_from(0.02, scene=True)
    print(f"scene [controller]: {scene_small:.3e} (tilt 0.01), {scene_large:.3e} (tilt 0.02)")
    assert np.array_equal(scene_run.t, run.t)
    assert scene_small < 10 * 0.01**3 and 5 < scene_large / scene_small < 11


def test_the_scenes_controller_and_a_python_controller_agree(source, tmp_path):
    # examples/wheeled_pendulum_discrete.toml's [controller] from the command line and from
    # Python's model.simulate(), and its law written as a Python controller: one loop
    # (app/sampled_run.hpp), the law evaluated from the scene's expressions or in Python.
    path = source / "examples" / "wheeled_pendulum_discrete.toml"
    scene = nhc.Scene.load(path)
    model = scene.build()
    gains = [scene.parameters[f"k{j}"] for j in range(1, 6)]
    k = {n: i for i, n in enumerate(model.state_names)}
    h, t_end = 0.01, 1.0
    options = dict(t_end=t_end, rtol=1e-11, atol=1e-13)
    from_scene = model.simulate(**options)
    assert from_scene.columns[-1] == "controller:z" and "input:TL" in from_scene.columns
    calls = []

    def law(t, y, z):
        s = [y[k["x"]], y[k["x'"]], y[k["th"]], y[k["th'"]], z]
        u = -sum(g * v for g, v in zip(gains, s))
        calls.append((t, z, u))
        return [u, u], z + h * y[k["x"]]

    from_python = model.simulate(controller=law, period=h, controller_state=0.0, **options)
    n = 100
    assert np.array_equal(from_scene.t, np.arange(n + 1) * h)  # t0 + k h exactly (t0 = 0)
    worst = max(float(np.max(np.abs(from_scene[name] - from_python[name]))) for name in model.state_names)
    print(f"scene [controller] against the Python controller: {worst:.3e}")
    assert worst <= 1e-9
    assert np.max(np.abs(from_scene["controller:z"] - np.array([c[1] for c in calls]))) <= 1e-9
    assert np.max(np.abs(from_scene["input:TL"] - np.array([c[2] for c in calls]))) <= 1e-9
    assert np.array_equal(from_scene["input:TL"], from_scene["input:TR"])
    assert abs(from_scene["th"][-1]) < 0.2 * abs(from_scene["th"][0])  # it holds the pendulum up
    # controller=False: the scene without its controller (open loop, it falls).
    falling = model.simulate(controller=False, t_end=0.5, outputs=5)
    assert falling["th"][-1] > 0.3
    # nhc simulate writes the same run.
    csv = tmp_path / "discrete.csv"
    done = subprocess.run([nhc_command(), "simulate", str(path), "--t-end", str(t_end), "--rtol", "1e-11",
                           "--atol", "1e-13", "-o", str(csv)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "sampled controller: period 0.01, 101 samples" in done.stdout
    table = csv_table(csv)
    assert list(table) == from_scene.columns
    for name in table:
        assert np.max(np.abs(table[name] - from_scene[name])) <= 1e-12 * (1 + np.max(np.abs(table[name]))), name


def test_scene_controller_refusals(source, tmp_path):
    path = source / "examples" / "wheeled_pendulum_discrete.toml"
    text = path.read_text()
    for flags, words in ((["--outputs", "10"], "--outputs: the scene's [controller] runs from sample to sample"),
                         (["--input", "TL=0"], "--input TL: the scene's [controller] sets it"),
                         (["--t-end", "0.005"], "is shorter than one period")):
        done = subprocess.run([nhc_command(), "simulate", str(path), *flags], capture_output=True, text=True)
        assert done.returncode == 2 and words in done.stderr and done.stdout == "", (flags, done.stderr)
    # nhc animate runs the scene's [controller] through the same engine (app/run_engine.hpp): its
    # rows are the samples, and the same refusals hold.
    done = subprocess.run([nhc_command(), "animate", str(path), "--t-end", "0.1", "-o", str(tmp_path / "a")],
                          capture_output=True, text=True)
    assert done.returncode == 0 and ", 11 samples," in done.stdout, done.stdout + done.stderr
    done = subprocess.run([nhc_command(), "animate", str(path), "--outputs", "10", "-o", str(tmp_path / "b")],
                          capture_output=True, text=True)
    assert done.returncode == 2 and "--outputs: the scene's [controller] runs from sample to sample" in done.stderr
    assert not (tmp_path / "b").exists()
    # An acceleration is not a state: located at the expression when the model is known.
    bad = tmp_path / "accelerating.toml"
    bad.write_text(text.replace('update = { z = "z + period*x" }', 'update = { z = "z + period*th\'\'" }'))
    done = subprocess.run([nhc_command(), "simulate", str(bad)], capture_output=True, text=True)
    line = next(n for n, l in enumerate(bad.read_text().splitlines(), 1) if l.startswith("update ="))
    assert done.returncode == 2 and f"accelerating.toml:{line}:" in done.stderr and "th''" in done.stderr, done.stderr
    with pytest.raises(nhc.SceneError, match="th''"):
        nhc.Scene.load(bad).build().simulate()
    with pytest.raises(nhc.SceneError, match="outputs"):
        nhc.Scene.load(path).build().simulate(outputs=10)
    with pytest.raises(nhc.SceneError, match="period"):
        nhc.Scene.load(source / "examples" / "wheeled_pendulum.toml").build().simulate(period=0.01, t_end=0.1)


SAMPLED_OSCILLATOR = """
name = "sampled_oscillator"
coordinates = ["x"]
lagrangian = "x'^2/2 - k*x^2/2"
[parameters]
k = 4.0
a = 0.5
w = 3.0
g = 1.5
[inputs]
u = "a*sin(w*t)"
v = "0"
[forces]
x = "u + v"
[initial]
x = [0.2, 0.0]
[controller]
period = 0.1
states = { s = 0.0 }
inputs = { v = "-g*x - s" }
update = { s = "s + period*x'" }
"""


def test_inputs_the_controller_does_not_set_keep_their_signals(tmp_path):
    # x'' = -k x + a sin(w t) + v, v = -g x_k - s_k held over [t_k, t_k+1), s_{k+1} = s_k + h x'_k:
    # against SciPy's solve_ivp interval by interval (the signal u continuous, v held).
    scipy_integrate = pytest.importorskip("scipy.integrate")
    run = nhc.Scene.from_toml(SAMPLED_OSCILLATOR).build().simulate(t_end=2.0, rtol=1e-11, atol=1e-13)
    k, a, w, g, h = 4.0, 0.5, 3.0, 1.5, 0.1
    state, s, rows = np.array([0.2, 0.0]), 0.0, []
    for j in range(21):
        t = j * h
        v = -g * state[0] - s
        rows.append((t, state[0], state[1], v, s))
        s = s + h * state[1]
        if j < 20:
            done = scipy_integrate.solve_ivp(lambda t, y: [y[1], -k * y[0] + a * np.sin(w * t) + v], (t, t + h), state,
                                             rtol=1e-12, atol=1e-14, method="DOP853")
            state = done.y[:, -1]
    rows = np.array(rows)
    assert np.array_equal(run.t, rows[:, 0])
    for c, name in enumerate(["x", "x'", "input:v", "controller:s"], start=1):
        assert np.max(np.abs(run[name] - rows[:, c])) < 1e-8, name
    assert np.max(np.abs(run["input:u"] - a * np.sin(w * run.t))) < 1e-15  # the signal, not held
