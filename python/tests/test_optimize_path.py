"""nhc.Scene.optimize proves its path (docs/optimize.md, "Path error"): an independent SciPy replay of
the optimal inputs agrees with the reported path error; spurious discrete optima are refused; the
solve leaves the GIL to other threads."""
import math
import threading

import numpy as np
import pytest

import nhc

integrate = pytest.importorskip("scipy.integrate")


def snakeboard_rates(p):
    """The snakeboard of examples/snakeboard_move.toml by hand, as Lagrange-d'Alembert equations: the
    kinetic energy's mass matrix is constant (q = x, y, theta, psi, phi), the axles' no-slip rows
    a1 = (-sin(theta+phi), cos(theta+phi), l cos(phi), 0, 0) and a2 = (-sin(theta-phi), cos(theta-phi),
    -l cos(phi), 0, 0) (sin(theta) sin(theta+-phi) + cos(theta) cos(theta+-phi) = cos(phi)), the
    torques u1 on psi and u2 on phi. M q'' = Q + A^T lambda with A q'' = -(dA/dt) q'."""
    m, J, Jr, Jw, l = p["m"], p["J"], p["Jr"], p["Jw"], p["l"]
    M = np.zeros((5, 5))
    M[0, 0] = M[1, 1] = m
    M[2, 2] = J + Jr + 2 * Jw
    M[2, 3] = M[3, 2] = Jr
    M[3, 3] = Jr
    M[4, 4] = 2 * Jw

    def rates(y, u):
        q, v = y[:5], y[5:]
        th, ph = q[2], q[4]
        s1, c1, s2, c2 = math.sin(th + ph), math.cos(th + ph), math.sin(th - ph), math.cos(th - ph)
        A = np.array([[-s1, c1, l * math.cos(ph), 0, 0], [-s2, c2, -l * math.cos(ph), 0, 0]])
        dA = np.array([[-c1 * (v[2] + v[4]), -s1 * (v[2] + v[4]), -l * math.sin(ph) * v[4], 0, 0],
                       [-c2 * (v[2] - v[4]), -s2 * (v[2] - v[4]), l * math.sin(ph) * v[4], 0, 0]])
        K = np.block([[M, -A.T], [A, np.zeros((2, 2))]])
        rhs = np.concatenate([[0, 0, 0, u[0], u[1]], -dA @ v])
        return np.concatenate([v, np.linalg.solve(K, rhs)[:5]])

    return rates


def test_snakeboard_replayed_by_scipy_agrees_with_the_reported_path_error(source):
    scene = nhc.Scene.load(source / "examples" / "snakeboard_move.toml")
    run = scene.optimize(intervals=160)  # from the default start: continuation 10, 40, 160
    s = run.summary
    assert s["status"] == "optimal" and s["local"]
    assert s["path_error"] <= 1e-6
    rates = snakeboard_rates({"m": 1.0, "J": 0.2, "Jr": 0.1, "Jw": 0.01, "l": 0.5})
    names = ["x", "y", "theta", "psi", "phi"]
    states = np.column_stack([run[n] for n in names] + [run[n + "'"] for n in names])
    t, u = run["t"], np.column_stack([run["u1"], run["u2"]])
    scale = np.maximum(1.0, np.max(np.abs(states[::2]), axis=0))
    y = states[0].copy()
    worst = 0.0
    for a in range(0, len(t) - 2, 2):
        ta, tm, tb = t[a], t[a + 1], t[a + 2]

        def inputs(tt, a=a, ta=ta, tm=tm, tb=tb):  # the quadratic through the interval's three points
            la = (tt - tm) * (tt - tb) / ((ta - tm) * (ta - tb))
            lm = (tt - ta) * (tt - tb) / ((tm - ta) * (tm - tb))
            lb = (tt - ta) * (tt - tm) / ((tb - ta) * (tb - tm))
            return la * u[a] + lm * u[a + 1] + lb * u[a + 2]

        done = integrate.solve_ivp(lambda tt, yy: rates(yy, inputs(tt)), (ta, tb), y, method="DOP853", rtol=1e-12, atol=1e-13)
        assert done.success
        y = done.y[:, -1]
        worst = max(worst, float(np.max(np.abs(y - states[a + 2]) / scale)))
    assert worst <= 1e-6
    assert 0.1 <= worst / s["path_error"] <= 10, (worst, s["path_error"])
    assert run["x"][-1] == pytest.approx(1.0) and np.all(np.abs(u) <= 0.5 + 1e-9)


def test_a_spurious_discrete_optimum_is_refused(source, tmp_path):
    # The Heisenberg loop with x held at 0 has no path; Hermite-Simpson's spurious mode meets every
    # point condition, the path error between the points does not.
    text = (source / "examples" / "heisenberg_optimal.toml").read_text().replace("z = 0.5\n", "z = 0.5\n[optimize.bounds]\nx = [0.0, 0.0]\n")
    path = tmp_path / "held.toml"
    path.write_text(text)
    with pytest.raises(nhc.MathError, match="not an optimum of the continuous problem: .*path error") as caught:
        nhc.Scene.load(path).optimize(intervals=20)
    assert caught.value.run.summary["path_error"] > 1e-3


def test_heisenberg_reports_its_path_error(source):
    run = nhc.Scene.load(source / "examples" / "heisenberg_optimal.toml").optimize(intervals=40)
    assert run.cost == pytest.approx(2 * math.pi * 0.5 / 1.0, rel=1e-6)
    assert 0 < run.summary["path_error"] <= 1e-6
    assert run.summary["path_error_measure"] == "quarter-point residuals"


def test_other_threads_run_during_the_solve(source):
    scene = nhc.Scene.load(source / "examples" / "snakeboard_move.toml")
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.001)

    worker = threading.Thread(target=count)
    worker.start()
    before = len(ticks)
    try:
        scene.optimize(intervals=40)
        during = len(ticks) - before
    finally:
        stop.set()
        worker.join()
    # Held for the whole solve, the GIL would let the counter run only between Python calls: a
    # handful of ticks at most; released, it ticks throughout the solve (about a second).
    assert during > 50, during


@pytest.fixture
def heisenberg(source):
    return nhc.Scene.load(source / "examples" / "heisenberg_optimal.toml")


def good_csv(heisenberg, tmp_path):
    first = heisenberg.optimize(intervals=10)
    path = tmp_path / "good.csv"
    path.write_text(",".join(first.columns) + "\n" + "\n".join(",".join(repr(float(v)) for v in row) for row in first.to_numpy()) + "\n")
    return first, path


def test_guess_files_under_the_data_file_rules(heisenberg, tmp_path):
    # docs/safety.md, "Reading: limits": the command line's reader and messages.
    import os
    first, good = good_csv(heisenberg, tmp_path)
    lines = good.read_text().splitlines()
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    big = tmp_path / "big.csv"
    with open(big, "wb") as f:
        f.truncate(65 << 20)
    nan_t = tmp_path / "nan_t.csv"
    nan_t.write_text(lines[0] + "\nnan," + lines[1].split(",", 1)[1] + "\n")
    short = tmp_path / "short.csv"
    short.write_text("\n".join(lines[:2] + [lines[2].rsplit(",", 1)[0]]) + "\n")
    escape = tmp_path / "escape.csv"
    escape.write_text(lines[0] + "\n" + lines[1] + "\n0.5,1\x1b[31m,0,0,0,0,0\n")
    cases = [(fifo, "is a FIFO"), ("/dev/zero", "is a character device"), (big, "is 65 MB, more than the 64 MB"),
             (nan_t, r"nan_t.csv:2:1: error: 'nan' is not a finite number"), (short, "short.csv:3:1: error: 6 cells, the header has 7"),
             (escape, r"escape.csv:3:5: error: '1\\x1b\[31m' is not a finite number")]
    for guess, words in cases:
        with pytest.raises(nhc.SceneError, match=words):
            heisenberg.optimize(intervals=10, guess=guess)
    crlf = tmp_path / "crlf.csv"
    crlf.write_bytes(good.read_bytes().replace(b"\n", b"\r\n"))
    assert heisenberg.optimize(intervals=10, guess=crlf).cost == pytest.approx(first.cost, rel=1e-9)


def test_guess_rows_wider_or_narrower_than_the_header_or_with_a_nan_t_are_refused(heisenberg, tmp_path):
    # Refused before any solve, so scripts/sanitize.sh runs this under AddressSanitizer
    # (python:guess_asan): a narrower row was read past its end, and a one-row guess whose t is
    # NaN crashed the interpreter.
    columns = ["t", "x", "x'", "y", "y'", "z", "z'"]
    for width, words in [(5, "row 1 has 5 values, the header 7 names"), (9, "row 1 has 9 values, the header 7 names")]:
        rows = np.zeros((3, width))
        rows[:, 0] = [0.0, 0.5, 1.0]
        with pytest.raises(nhc.SceneError, match=words):
            heisenberg.optimize(intervals=10, guess=nhc.Run({"columns": columns, "data": rows, "summary": {}}))
    one = np.zeros((1, 7))
    one[0, 0] = float("nan")
    with pytest.raises(nhc.SceneError, match=r"row 1, column 1 \('t'\) is nan, not a finite number"):
        heisenberg.optimize(intervals=10, guess=nhc.Run({"columns": columns, "data": one, "summary": {}}))
    nan_t = tmp_path / "nan_t.csv"
    nan_t.write_text(",".join(columns) + "\nnan,0,0,0,0,0,0\n")
    with pytest.raises(nhc.SceneError, match=r"nan_t.csv:2:1: error: 'nan' is not a finite number"):
        heisenberg.optimize(intervals=10, guess=nan_t)


def test_a_run_guess_is_checked_against_its_header(heisenberg):
    first = heisenberg.optimize(intervals=10)
    narrow = nhc.Run({"columns": first.columns, "data": first.to_numpy()[:, :-2], "summary": {}})
    with pytest.raises(nhc.SceneError, match="row 1 has 5 values, the header 7 names"):
        heisenberg.optimize(intervals=10, guess=narrow)
    data = first.to_numpy().copy()
    data[0, 0] = float("nan")
    with pytest.raises(nhc.SceneError, match=r"row 1, column 1 \('t'\) is nan, not a finite number"):
        heisenberg.optimize(intervals=10, guess=nhc.Run({"columns": first.columns, "data": data, "summary": {}}))
