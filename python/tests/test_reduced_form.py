"""The multiplier-free (Maggi) form M_r u' = f_r through Derivation.to_sympy(), against
independent paths: hand derivations in docs/reduced-form.md, the benchmark bicycle's mass
matrix (Meijaard et al. 2007), and the multipliers of the DAE run."""
import os

import numpy as np
import pytest

import nhc

sp = pytest.importorskip("sympy")


def numeric(eqs, e, values):
    """e at `values` (name -> number), the definitions evaluated one by one in their order."""
    point = {eqs.symbol(n): v for n, v in values.items() if n in eqs.symbols}
    for name, d in eqs.definitions.items():
        point[eqs.symbol(name)] = sp.Float(d.xreplace(point).evalf(30), 30)
    return complex(e.xreplace(point).evalf(30))


def test_sleigh_matches_the_hand_derivation(source):
    # docs/reduced-form.md, "The Chaplygin sleigh": speeds (x', th'), y' = tan(th) x'.
    eqs = nhc.Scene.load(source / "examples/chaplygin_sleigh.toml").derive("chetaev").to_sympy()
    assert eqs.speeds == ["x'", "th'"]
    m, J, a, b, k, th = (eqs.symbol(n) for n in ("m", "J", "a", "b", "k", "th"))
    xd, thd = eqs.symbol("x'"), eqs.symbol("th'")
    M = sp.Matrix([[m / sp.cos(th)**2, 0], [0, J + m * a**2]])
    f = sp.Matrix([-b * xd / sp.cos(th)**2 + m * a * thd**2 / sp.cos(th)
                   - m * sp.sin(th) * thd * xd / sp.cos(th)**3,
                   -k * thd - m * a * thd * xd / sp.cos(th)])
    assert sp.simplify(eqs.expand(eqs.mass_matrix) - M) == sp.zeros(2, 2)
    assert sp.simplify(eqs.expand(eqs.forcing) - f) == sp.zeros(2, 1)
    assert sp.simplify(eqs.expand(eqs.dependent_speeds["y'"]) - sp.tan(th) * xd) == 0


def test_knife_edge_multiplier_equals_the_dae_run(source):
    text = (source / "examples/knife_edge.toml").read_text()
    text = text.replace("x = [0.0]", "x = [0.0, 1.0]").replace("phi = [0.0]", "phi = [0.0, 0.7]")
    scene = nhc.Scene.from_toml(text)
    eqs = scene.derive("chetaev").to_sympy(speeds=["x'", "phi'"])
    run = scene.build("chetaev").simulate(t_end=1.0, rtol=1e-13, atol=1e-15)
    u_dot = eqs.mass_matrix.LUsolve(eqs.forcing)
    lam = eqs.expand(eqs.multipliers["lambda1"].subs({eqs.symbol("x''"): u_dot[0], eqs.symbol("phi''"): u_dot[1]}))
    f = sp.lambdify([eqs.symbol(n) for n in ("phi", "x'", "phi'", "m", "J")], eqs.expand(lam))
    p = scene.parameters
    reduced = np.array([f(run["phi"][i], run["x'"][i], run["phi'"][i], p["m"], p["J"])
                        for i in range(len(run.t))])
    assert np.max(np.abs(reduced - run["lambda1"])) < 1e-10
    assert np.max(np.abs(run["lambda1"])) > 0.1  # the constraint force is not zero


@pytest.mark.skipif(os.environ.get("NHC_SLOW_TESTS") != "1",
                    reason="about 15 s: ctest python:reduced_form_bicycle (label slow) runs it")
def test_bicycle_mass_matrix_is_the_benchmark(source):
    # Meijaard, Papadopoulos, Ruina, Schwab (2007), Table 2: M for lean and steer.
    scene = nhc.Scene.load(source / "examples/whipple/whipple_bicycle.toml")
    eqs = scene.derive("chetaev").to_sympy(speeds=["phi'", "delta'", "thr'"])
    assert eqs.speeds == ["phi'", "delta'", "thr'"]
    values = dict(scene.parameters)
    values.update({n: 0.0 for n in scene.coordinates})
    values.update({"Tphi": 0.0, "Tdelta": 0.0, "t": 0.0})
    values.update({n + "'": 0.0 for n in scene.coordinates})
    values.update({n + "''": 0.0 for n in scene.coordinates})
    M = [[numeric(eqs, eqs.mass_matrix[i, j], values) for j in range(2)] for i in range(2)]
    # The scene's z points up, the paper's down: the steer angle about the (near-vertical) steering
    # axis changes sign, lean about the forward x axis does not, so M_phi,delta changes sign.
    benchmark = [[80.81722, -2.31941332208709], [-2.31941332208709, 0.29784188199686]]
    for i in range(2):
        for j in range(2):
            assert abs(M[i][j].imag) < 1e-20
            assert abs(M[i][j].real - benchmark[i][j]) < 1e-12
    # Upright, lean and steer do not couple to the wheel's rotation.
    assert abs(numeric(eqs, eqs.mass_matrix[0, 2], values)) < 1e-12


def test_bad_speeds_are_refused_in_words(source):
    scene = nhc.Scene.load(source / "examples/knife_edge.toml")
    with pytest.raises(nhc.SceneError, match="speeds"):
        scene.derive("chetaev").to_sympy(speeds=["z'", "phi'"])
    with pytest.raises(nhc.SceneError, match="3 coordinates and 1 constraints"):
        scene.derive("chetaev").to_sympy(speeds=["x'"])


def test_vakonomic_has_no_reduced_form(source):
    eqs = nhc.Scene.load(source / "examples/knife_edge.toml").derive("vakonomic").to_sympy()
    assert eqs.speeds is None and "chetaev and holder" in eqs.reduced_reason
    assert set(eqs.residuals) == {"R_x", "R_y", "R_phi"}


def test_rolling_disk_matches_the_hand_derivation(source):
    # docs/reduced-form.md, "The rolling disk": T* = m r^2/2 [5/4 phi'^2 + 3/2 (psi' sin(phi) + ph')^2
    # + 1/4 psi'^2 cos(phi)^2], V = m g r cos(phi); M_r is the Hessian of T* in the speeds, and at
    # rest f_r = -dV/d(psi, phi, ph).
    eqs = nhc.Scene.load(source / "examples/rolling_disk.toml").derive("chetaev").to_sympy()
    assert eqs.speeds == ["psi'", "phi'", "ph'"]
    m, r, g, phi = (eqs.symbol(n) for n in ("m", "r", "g", "phi"))
    u = [eqs.symbol(n) for n in eqs.speeds]
    T = m * r**2 / 2 * (sp.Rational(5, 4) * u[1]**2 + sp.Rational(3, 2) * (u[0] * sp.sin(phi) + u[2])**2
                        + sp.Rational(1, 4) * u[0]**2 * sp.cos(phi)**2)
    M = sp.hessian(T, u)
    assert sp.simplify(eqs.expand(eqs.mass_matrix) - M) == sp.zeros(3, 3)
    at_rest = eqs.expand(eqs.forcing).subs({s: 0 for s in u})
    assert sp.simplify(at_rest - sp.Matrix([0, m * g * r * sp.sin(phi), 0])) == sp.zeros(3, 1)


def integrate_reduced(model, run, t_end):
    """The ODE q' = velocities(t, q, u), u' = M_r^-1 f_r from the model's generated functions,
    integrated by SciPy (DOP853, tight tolerances) from the run's first row, at the run's times."""
    integrate = pytest.importorskip("scipy.integrate")
    n = len(model.coordinates)
    q0 = [run[c][0] for c in model.coordinates]
    u0 = [run[s][0] for s in model.speeds]

    def rhs(t, x):
        q, u = x[:n], x[n:]
        return np.concatenate([model.velocities(t, q, u),
                               np.linalg.solve(model.mass_matrix(t, q, u), model.forcing(t, q, u))])

    return integrate.solve_ivp(rhs, (run.t[0], t_end), np.concatenate([q0, u0]), method="DOP853",
                               t_eval=run.t, rtol=1e-13, atol=1e-13)


def assert_follows_the_run(model, run, t_end):
    solution = integrate_reduced(model, run, t_end)
    assert solution.success, solution.message
    n = len(model.coordinates)
    names = model.coordinates + model.speeds
    worst = max(np.max(np.abs(solution.y[k] - run[name])) for k, name in enumerate(names))
    assert worst < 1e-8, worst
    # The dependent speeds from velocities() at the run's q and u equal the run's.
    for i in range(0, len(run.t), 50):
        q = [run[c][i] for c in model.coordinates]
        qp = model.velocities(run.t[i], q, [run[s][i] for s in model.speeds])
        for j, c in enumerate(model.coordinates):
            assert abs(qp[j] - run[c + "'"][i]) < 1e-8


def test_header_ode_of_the_rolling_disk_follows_simulate(source):
    # The generated mass_matrix/forcing/velocities (Reduced-form additions), not to_sympy():
    # the disk started off its steady circle (lean rate 0.2) so that every speed changes.
    text = (source / "examples/rolling_disk.toml").read_text().replace("phi = [0.3, 0.0]", "phi = [0.3, 0.2]")
    model = nhc.Scene.from_toml(text).build("chetaev")
    assert model.speeds == ["psi'", "phi'", "ph'"]
    assert model.speed_coordinates == [2, 3, 4]
    run = model.simulate(t_end=2.0, rtol=1e-13, atol=1e-14, outputs=201)
    assert np.ptp(run["phi"]) > 0.05  # the lean moves
    assert_follows_the_run(model, run, 2.0)


def test_header_ode_of_the_sleigh_follows_simulate(source):
    model = nhc.Scene.load(source / "examples/chaplygin_sleigh.toml").build("chetaev")
    assert model.speeds == ["x'", "th'"]
    run = model.simulate(t_end=5.0, rtol=1e-13, atol=1e-14, outputs=501)
    assert_follows_the_run(model, run, 5.0)


def test_a_model_without_the_reduced_form_says_so(source):
    model = nhc.Scene.load(source / "examples/chaplygin_sleigh.toml").build("vakonomic")
    assert model.speeds == []
    with pytest.raises(nhc.MathError, match="no multiplier-free form"):
        model.mass_matrix(0.0, [0.0, 0.0, 0.0], [])


@pytest.mark.skipif(os.environ.get("NHC_SLOW_TESTS") != "1",
                    reason="the bicycle's compile: ctest python:reduced_form_bicycle (label slow) runs it")
def test_header_ode_of_the_bicycle_follows_simulate(source):
    # Default speeds phi', delta', thf' (the scene's dependent key); atol 1e-14 fails IDA's
    # consistent initialization here, 1e-13 agrees to 1.2e-11.
    model = nhc.Scene.load(source / "examples/whipple/whipple_bicycle.toml").build("chetaev")
    assert model.speeds == ["phi'", "delta'", "thf'"]
    run = model.simulate(t_end=5.0, rtol=1e-13, atol=1e-13, outputs=501)
    assert_follows_the_run(model, run, 5.0)
