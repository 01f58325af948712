"""Events ([events], stop_when, run.events) against an independent path: the rolling disk of
examples/rolling_disk.toml started leaning with little yaw and no spin falls; the time its lean
reaches 1.2 rad is found again here by a model derived with SymPy (Lagrange-d'Alembert
equations of the same kinematics, the multipliers eliminated numerically) integrated by SciPy's
DOP853 with its own event location."""
import re

import numpy as np
import pytest

import nhc

sp = pytest.importorskip("sympy")
integrate = pytest.importorskip("scipy.integrate")

M, R, G = 1.0, 0.5, 9.81
PSI_RATE, PHI0 = 0.5, 0.3  # yaw rate and lean at t = 0; no spin: the disk falls


def falling_disk(source):
    """examples/rolling_disk.toml started off its steady motion, with the lean event."""
    text = (source / "examples" / "rolling_disk.toml").read_text()
    text = re.sub(r"^psi = .*$", f"psi = [0.0, {PSI_RATE!r}]", text, flags=re.M)
    text = re.sub(r"^phi = .*$", f"phi = [{PHI0!r}, 0.0]", text, flags=re.M)
    text = re.sub(r"^ph = .*$", "ph = [0.0, 0.0]", text, flags=re.M)
    text = re.sub(r"^\[events\].*?(?=^\[|\Z)", "", text, flags=re.M | re.S)  # the example's own
    return text + '\n[events]\nfallen = { when = "phi - 1.2", direction = "up", action = "stop" }\n' \
                  'halfway = { when = "phi - 0.6", direction = "up", action = "record" }\n'


def sympy_disk():
    """q'' and the constraint matrix of the disk, derived here: L = T - V of a thin uniform disk,
    centre c = (x, y, 0) + r P e_z with P = Rz(psi) Rx(phi), the contact point's velocity
    c' + w x (-r P e_z) = 0 (two horizontal components), w the disk's angular velocity."""
    t = sp.Symbol("t")
    names = ["x", "y", "psi", "phi", "ph"]
    q = [sp.Function(n)(t) for n in names]
    x, y, psi, phi, ph = q
    qd = [sp.diff(v, t) for v in q]

    def rx(a):
        return sp.Matrix([[1, 0, 0], [0, sp.cos(a), -sp.sin(a)], [0, sp.sin(a), sp.cos(a)]])

    def ry(a):
        return sp.Matrix([[sp.cos(a), 0, sp.sin(a)], [0, 1, 0], [-sp.sin(a), 0, sp.cos(a)]])

    def rz(a):
        return sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])

    P = rz(psi) * rx(phi)
    Rd = P * ry(ph)
    ez = sp.Matrix([0, 0, 1])
    c = sp.Matrix([x, y, 0]) + R * P * ez
    W = Rd.diff(t) * Rd.T  # spatial angular velocity, skew (left unsimplified: numbers follow)
    w = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
    wb = Rd.T * w  # body frame: axle along y
    T = M / 2 * c.diff(t).dot(c.diff(t)) + M * R**2 / 8 * (wb[0]**2 + wb[2]**2) + M * R**2 / 4 * wb[1]**2
    L = T - M * G * c[2]
    slip = c.diff(t) + w.cross(-R * P * ez)
    f = sp.Matrix([slip[0], slip[1]])
    # Plain symbols for the jet.
    Q = sp.symbols("q0:5")
    V = sp.symbols("v0:5")
    to_plain = {**{qd[i]: V[i] for i in range(5)}, **{q[i]: Q[i] for i in range(5)}}
    L = L.subs(to_plain)
    f = f.subs(to_plain)
    v = sp.Matrix(V)
    p = sp.Matrix([sp.diff(L, vi) for vi in V])
    mass = p.jacobian(V)
    bias = p.jacobian(Q) * v - sp.Matrix([sp.diff(L, qi) for qi in Q])
    A = f.jacobian(V)
    A_dot_v = f.jacobian(Q) * v
    return sp.lambdify([Q, V], [mass, bias, A, A_dot_v], "numpy", cse=True)


def test_rolling_disk_lean_event_matches_an_independent_model(source, tmp_path):
    parts = sympy_disk()

    def rhs(_t, s):
        qv, vv = s[:5], s[5:]
        mass, bias, A, A_dot_v = (np.asarray(m, dtype=float) for m in parts(qv, vv))
        # [M  -A^T; A 0] [q''; lambda] = [-bias; -A' q']: Lagrange-d'Alembert with A q' = 0.
        K = np.block([[mass, -A.T], [A, np.zeros((2, 2))]])
        sol = np.linalg.solve(K, np.concatenate([-bias.ravel(), -A_dot_v.ravel()]))
        return np.concatenate([vv, sol[:5]])

    q0 = np.array([0.0, 0.0, 0.0, PHI0, 0.0])
    v0 = np.array([0.0, 0.0, PSI_RATE, 0.0, 0.0])
    A0 = np.asarray(parts(q0, v0)[2], dtype=float)
    v0[:2] = np.linalg.solve(A0[:, :2], -A0[:, 2:] @ v0[2:])  # x', y' from the rolling constraints

    def lean(_t, s):
        return s[3] - 1.2
    lean.terminal, lean.direction = True, 1

    def half(_t, s):
        return s[3] - 0.6
    half.direction = 1
    ref = integrate.solve_ivp(rhs, (0.0, 5.0), np.concatenate([q0, v0]), method="DOP853", rtol=1e-13, atol=1e-13,
                              events=[lean, half])
    assert ref.status == 1  # ended by the lean event
    t_fallen, t_half = ref.t_events[0][0], ref.t_events[1][0]

    scene = nhc.Scene.from_toml(falling_disk(source))
    run = scene.build("chetaev").simulate(t_end=5.0, rtol=1e-11, atol=1e-13, outputs=50)
    assert [e.name for e in run.events] == ["halfway", "fallen"]
    assert abs(run.events[0].t - t_half) < 1e-7
    assert abs(run.events[1].t - t_fallen) < 1e-7
    assert abs(run.events[1].state["phi"] - 1.2) < 1e-8
    assert run.t[-1] == pytest.approx(run.events[1].t, abs=0)  # a stop event ends the run there
    # stop_when: the same crossing, as the command line's --stop-when.
    again = nhc.Scene.from_toml(falling_disk(source).split("[events]")[0]).build("chetaev")
    stopped = again.simulate(t_end=5.0, rtol=1e-11, atol=1e-13, stop_when="phi - 1.2")
    assert [e.name for e in stopped.events] == ["stop_when"]
    assert abs(stopped.events[0].t - t_fallen) < 1e-7


def test_event_directions_and_bad_events():
    # x = cos(2 t): x crosses 0 downwards at pi/4, upwards at 3 pi/4.
    text = """
name = "oscillator"
coordinates = ["x"]
lagrangian = "x'^2/2 - 2*x^2"
[initial]
x = [1.0, 0.0]
[events]
down = { when = "x", direction = "down", action = "record" }
up = { when = "x", direction = "up", action = "record" }
"""
    run = nhc.Scene.from_toml(text).build("chetaev").simulate(t_end=4.0, rtol=1e-10, atol=1e-12)
    assert [e.name for e in run.events] == ["down", "up", "down"]
    for e, k in zip(run.events, [1, 3, 5]):
        assert abs(e.t - k * np.pi / 4) < 1e-8
    with pytest.raises(nhc.SceneError, match="direction 'sideways': up, down or any"):
        nhc.Scene.from_toml(text.replace('"down", action', '"sideways", action'))
    with pytest.raises(nhc.SceneError, match="stop_when"):
        nhc.Scene.from_toml(text).build("chetaev").simulate(stop_when="x +")
