"""nhc.Model, nhc.Run and Scene.linearize, each against an independent answer: closed forms,
finite differences, the benchmark's Table 2."""
import math
import threading

import numpy as np
import pytest

import nhc

OSCILLATOR = """
name = "oscillator"
coordinates = ["x"]
lagrangian = "x'^2/2 - k*x^2/2"
[parameters]
k = 4.0
[initial]
x = [1.0, 0.0]
[invariants]
energy = "x'^2/2 + k*x^2/2"
"""


def test_simulate_follows_the_closed_form():
    # x'' = -k x from x = 1 at rest: x = cos(sqrt(k) t), energy k/2.
    run = nhc.Scene.from_toml(OSCILLATOR).build("chetaev").simulate(t_end=5, rtol=1e-10, atol=1e-12, outputs=100)
    assert run.columns[:4] == ["t", "x", "x'", "x''"]
    assert len(run) == 101 and run.to_numpy().shape == (101, len(run.columns))
    assert np.max(np.abs(run["x"] - np.cos(2.0 * run.t))) < 1e-8
    assert np.max(np.abs(run["x'"] + 2.0 * np.sin(2.0 * run.t))) < 1e-7
    assert run.summary["steps"] > 0
    assert run.summary["invariant_drift"]["energy"] < 1e-7
    with pytest.raises(KeyError, match="no column 'v'"):
        run["v"]


def test_output_times_and_set():
    scene = nhc.Scene.from_toml(OSCILLATOR, set={"k": 9.0})
    run = scene.build("chetaev").simulate(output_times=np.array([0.0, 0.5, 1.0]), rtol=1e-10, atol=1e-12)
    assert list(run.t) == [0.0, 0.5, 1.0]
    assert run["x"] == pytest.approx(np.cos(3.0 * run.t), abs=1e-8)


def test_residual_and_jacobian_agree_with_finite_differences():
    model = nhc.Scene.from_toml(OSCILLATOR).build("chetaev")
    rng = np.random.default_rng(7)
    y, yp, cj, h = rng.normal(size=2), rng.normal(size=2), 3.0, 1e-6
    J = model.jacobian(0.3, y, yp, cj)
    for j in range(2):
        e = np.zeros(2)
        e[j] = h
        dy = (model.residual(0.3, y + e, yp) - model.residual(0.3, y - e, yp)) / (2 * h)
        dyp = (model.residual(0.3, y, yp + e) - model.residual(0.3, y, yp - e)) / (2 * h)
        assert J[:, j] == pytest.approx(dy + cj * dyp, abs=1e-8)
    with pytest.raises(nhc.SceneError, match="vector of 2 numbers"):
        model.residual(0.0, np.zeros(3), np.zeros(2))


def test_a_failure_is_a_math_error_at_its_time(source):
    # Appell-Hamel (chetaev) stops where the horizontal speed vanishes: t* = v0 (a^2 + b^2) / (g a b).
    model = nhc.Scene.load(source / "examples" / "appell_hamel.toml").build("chetaev")
    with pytest.raises(nhc.MathError) as caught:
        model.simulate(t_end=1.0, rtol=1e-10, atol=1e-12)
    t_star = math.hypot(1.0, 0.5) * (1.0 + 0.25) / (9.81 * 0.5)
    assert caught.value.t == pytest.approx(t_star, rel=1e-5)
    assert caught.value.run.t[-1] <= caught.value.t


def test_a_failure_at_a_singularity_of_euler_angles_names_the_angle(source):
    # A ball rolling on a turntable in z-x-z angles; th reaches pi near t = 0.31
    # (tests/cli/scenes/ball_turntable_zxz.toml, and tests/cli/euler_angles_test.cpp).
    scene = nhc.Scene.load(source / "tests" / "cli" / "scenes" / "ball_turntable_zxz.toml")
    model = scene.build()
    with pytest.raises(nhc.MathError) as caught:
        model.simulate()
    words = str(caught.value)
    assert words.startswith("the z-x-z Euler angles psi, th, ph are close to their singularity at t = ")
    assert "(z-x-z angles are singular at th = 0, pi: " in words
    assert "write the attitude with quat(q0, q1, q2, q3)" in words
    assert 0.25 < caught.value.t < 0.35
    assert abs(math.sin(caught.value.run["th"][-1])) < 0.1
    # Short of it, the same scene runs.
    run = model.simulate(t_end=0.2)
    assert run.t[-1] == pytest.approx(0.2)


def test_linearize_gives_the_benchmark_eigenvalues_and_b(source):
    # Meijaard et al. (2007), Table 2 at 5 m/s; B's lean and steer rows are S M^-1 S (docs/linearize.md).
    lin = nhc.Scene.load(source / "examples" / "whipple" / "whipple_bicycle.toml").linearize(at={"phi'": 0.0})
    for want in [-14.07838969279822, -0.77534188219585 + 4.46486771378823j, -0.32286642900409]:
        assert np.min(np.abs(lin.eigenvalues - want)) < 1e-10 * abs(want)
    M = np.array([[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]])
    S = np.diag([1.0, -1.0])
    rows = [lin.states.index("phi'"), lin.states.index("delta'")]
    assert lin.B[rows, :] == pytest.approx(S @ np.linalg.inv(M) @ S, rel=1e-10)
    assert lin.inputs == ["Tphi", "Tdelta"]
    assert lin.verdict == "asymptotically_stable"


def test_two_threads_simulate_at_once():
    scene = nhc.Scene.from_toml(OSCILLATOR)
    model = scene.build("chetaev")
    alone = model.simulate(t_end=3, rtol=1e-10, atol=1e-12)
    results = [None, None]

    def work(k):
        results[k] = model.simulate(t_end=3, rtol=1e-10, atol=1e-12)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for run in results:
        assert np.array_equal(run.to_numpy(), alone.to_numpy())


def test_sweep_finds_the_weave_and_capsize_speeds(source):
    # Meijaard et al. (2007), Table 2: weave 4.29238253634111, capsize 6.02426201538837 m/s.
    bike = nhc.Scene.load(source / "examples" / "whipple" / "whipple_bicycle.toml")
    sw = bike.sweep("chetaev", "v", np.linspace(4, 7, 4), at={"phi'": 0})
    assert sw.verdicts == ["unstable", "asymptotically_stable", "asymptotically_stable", "unstable"]
    speeds = [t["value"] for t in sw.thresholds]
    assert speeds == pytest.approx([4.29238253634111, 6.02426201538837], rel=1e-10)
    with pytest.raises(nhc.SceneError, match="equally spaced"):
        bike.sweep("chetaev", "v", [4.0, 4.5, 7.0])


def test_compare_runs_every_model():
    # Without constraints every model is Lagrange's equations: each follows cos(2t).
    runs = nhc.compare(nhc.Scene.from_toml(OSCILLATOR), ["chetaev", "vakonomic", "holder"], t_end=2, rtol=1e-10,
                       atol=1e-12)
    assert sorted(runs) == ["chetaev", "holder", "vakonomic"]
    for run in runs.values():
        assert np.max(np.abs(run["x"] - np.cos(2.0 * run.t))) < 1e-8


DRIVEN = """
name = "driven"
coordinates = ["x"]
lagrangian = "x'^2/2 - x^2/2"
[inputs]
F = "0"
[forces]
x = "F"
[initial]
x = [1.0, 0.5]
"""


def test_inputs_from_a_python_function():
    # x'' = -x + F. A feedback F = -2 x' is critical damping: x = (x0 + (v0 + x0) t) e^-t.
    model = nhc.Scene.from_toml(DRIVEN).build("chetaev")
    assert model.inputs == ["F"]
    velocity = model.state_names.index("x'")
    run = model.simulate(t_end=5, rtol=1e-10, atol=1e-12, inputs=lambda t, y: [-2.0 * y[velocity]])
    assert np.max(np.abs(run["x"] - (1.0 + 1.5 * run.t) * np.exp(-run.t))) < 1e-8
    assert run["input:F"] == pytest.approx(-2.0 * run["x'"], abs=1e-12)
    # An exception in the function comes out as itself.
    def broken(t, y):
        raise ZeroDivisionError("no input here")
    with pytest.raises(ZeroDivisionError, match="no input here"):
        model.simulate(t_end=1, inputs=broken)
    with pytest.raises(TypeError, match="returned 2 values"):
        model.simulate(t_end=1, inputs=lambda t, y: [0.0, 1.0])
    # numpy reads None as NaN: the run would fail with "residual R_x is NaN" without naming the cause.
    def forgot_return(t, y):
        -2.0 * y[velocity]
    with pytest.raises(TypeError, match="forgot_return returned None"):
        model.simulate(t_end=1, inputs=forgot_return)


@pytest.mark.parametrize("arguments, words", [
    (dict(output_times=[-1, 0.5, 1]), "first time is before t0 = 0"),
    (dict(output_times=[0, 0.5, 0.2, 1], integrator="variational", step=0.01), "the times must increase"),
    (dict(output_times=[0, 0.5, 0.2, 1]), "the times must increase"),
    (dict(output_times=[0, float("nan"), 1]), "nan is not a finite number"),
    (dict(output_times=[0]), "the last time must be after t0"),
    (dict(t_end=float("nan")), "t_end: nan is not a finite number"),
    (dict(t_end=-1), "t_end -1 must be after t0 = 0"),
    (dict(atol=float("inf")), "atol: inf is not a positive number"),
    (dict(atol=0), "atol: 0 is not a positive number"),
    (dict(rtol=1e10), "rtol: 10000000000 is not below 1"),
    (dict(rtol=1e-17), "below the double-precision machine epsilon"),
    (dict(rtol=float("nan")), "rtol: nan is not a positive number"),
    (dict(outputs=0), "outputs: 0 is not a whole number from 1 to 10000000"),
    (dict(outputs=-5), "outputs: -5 is not a whole number from 1 to 10000000"),
    (dict(outputs=10**30), "outputs: .* is not a whole number from 1 to 10000000"),
    (dict(outputs=2.5), "outputs: 2.5 is not a whole number"),
    (dict(max_steps=0), "max_steps: 0 is not a whole number"),
    (dict(integrator="variational", step=float("nan")), "step: nan is not a positive number"),
])
def test_run_arguments_obey_the_command_lines_rules(arguments, words):
    # The rules of --output-times, --t-end, --rtol, --atol, --outputs, --max-steps and --step
    # (nhc/app/run_request.hpp): each breach is an nhc.SceneError naming the argument, never a run.
    model = nhc.Scene.from_toml(OSCILLATOR).build("chetaev")
    with pytest.raises(nhc.SceneError, match=words) as caught:
        model.simulate(**arguments)
    assert caught.value.file == next(iter(arguments)) or caught.value.file in arguments


def test_set_values_obey_the_command_lines_rules():
    for value in (float("nan"), float("inf")):
        with pytest.raises(nhc.SceneError, match="set k: .* is not a finite number"):
            nhc.Scene.from_toml(OSCILLATOR, set={"k": value})
    # A NaN parameter would reach GiNaC's evaluation in analyze (a raw RuntimeError before).
    assert nhc.Scene.from_toml(OSCILLATOR, set={"k": 9.0}).analyze().initial_point["x''"] == pytest.approx(-9.0)


def test_simulate_takes_the_scenes_simulate_values():
    # [simulate] t_end, outputs, rtol and atol are the defaults, as for nhc simulate.
    scene = nhc.Scene.from_toml(OSCILLATOR + "[simulate]\nt_end = 2.5\noutputs = 5\nrtol = 1e-11\natol = 1e-13\n")
    run = scene.build("chetaev").simulate()
    assert list(run.t) == pytest.approx([0.0, 0.5, 1.0, 1.5, 2.0, 2.5])
    assert np.max(np.abs(run["x"] - np.cos(2.0 * run.t))) < 1e-9
    assert len(scene.build("chetaev").simulate(t_end=1)) == 6


def test_ctrl_c_stops_a_long_run():
    # A run of about 3 10^6 steps (seconds): SIGINT to this process after 0.2 s must end it with
    # KeyboardInterrupt, as Ctrl-C would.
    import os
    import signal

    model = nhc.Scene.from_toml(OSCILLATOR).build("chetaev")
    timer = threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            model.simulate(t_end=1e5, outputs=100000, max_steps=10**9)
    finally:
        timer.cancel()


def test_sensitivities_follow_the_closed_form():
    # x = x0 cos(w t) + v0 sin(w t)/w with w = sqrt(k), x0 = 1, v0 = 0, k = 4:
    # dx/dk = -t sin(w t)/(2 w), dx/dx0 = cos(w t), dx/dv0 = sin(w t)/w.
    model = nhc.Scene.from_toml(OSCILLATOR).build("chetaev")
    run = model.simulate(t_end=3, rtol=1e-10, atol=1e-12, outputs=60, sensitivity=["k", "x(0)", "x'(0)"])
    t, w = run.t, 2.0
    assert run["x"] == pytest.approx(np.cos(w * t), abs=1e-8)
    assert run["d(x)/d(k)"] == pytest.approx(-t * np.sin(w * t) / (2 * w), abs=1e-7)
    assert run["d(x')/d(k)"] == pytest.approx(-(np.sin(w * t) + w * t * np.cos(w * t)) / (2 * w), abs=1e-7)
    assert run["d(x)/d(x(0))"] == pytest.approx(np.cos(w * t), abs=1e-7)
    assert run["d(x)/d(x'(0))"] == pytest.approx(np.sin(w * t) / w, abs=1e-7)
    assert run.summary["sensitivity_residual_evaluations"] > 0
    assert [c for c in run.columns if c.startswith("d(")][:2] == ["d(x)/d(k)", "d(x')/d(k)"]


def test_sensitivity_names_are_checked():
    model = nhc.Scene.from_toml(OSCILLATOR).build("chetaev")
    with pytest.raises(nhc.SceneError, match="unknown parameter m"):
        model.simulate(t_end=1, sensitivity=["m"])
    with pytest.raises(nhc.SceneError, match="named twice"):
        model.simulate(t_end=1, sensitivity=["k", "k"])
    with pytest.raises(nhc.SceneError, match="sensitivity"):
        model.simulate(t_end=1, sensitivity=[])


def test_sensitivity_to_the_slope_of_the_incline(source):
    # examples/knife_edge_incline.toml: x = g sin(alpha)/(2 w^2) sin^2(w t), so
    # dx/dalpha = g cos(alpha)/(2 w^2) sin^2(w t); y' = 0 at the start is not given (the constraint fixes it).
    scene = nhc.Scene.load(source / "examples/knife_edge_incline.toml")
    model = scene.build("chetaev")
    run = model.simulate(t_end=1, rtol=1e-10, atol=1e-12, outputs=40, sensitivity=["alpha", "x'(0)"])
    g, alpha, w = 9.81, 0.3, 2.0
    expected = g * math.cos(alpha) / (2 * w**2) * np.sin(w * run.t) ** 2
    assert run["d(x)/d(alpha)"] == pytest.approx(expected, abs=1e-6)
    with pytest.raises(nhc.SceneError, match="y'\\(0\\) is not given"):
        model.simulate(t_end=1, sensitivity=["y'(0)"])


def test_variational_integrator_converges_with_order_two_and_keeps_the_energy():
    # The midpoint discrete Lagrangian on x'' = -k x (docs/variational.md): error O(h^2) against
    # cos(2t); the energy error oscillates, it does not grow with the length of the run.
    model = nhc.Scene.from_toml(OSCILLATOR).build("chetaev")
    errors = []
    for h in (0.02, 0.01):
        run = model.simulate(t_end=5, outputs=50, integrator="variational", step=h)
        assert run.columns == model.simulate(t_end=5, outputs=50).columns
        errors.append(np.max(np.abs(run["x"] - np.cos(2.0 * run.t))))
        assert run.summary["newton_iterations"] >= run.summary["steps"]
    assert math.log2(errors[0] / errors[1]) == pytest.approx(2.0, abs=0.05)
    brief = model.simulate(t_end=10, outputs=1000, integrator="variational", step=0.01)
    lasting = model.simulate(t_end=1000, outputs=100000, integrator="variational", step=0.01)
    assert lasting.summary["invariant_drift"]["energy"] <= 1.5 * brief.summary["invariant_drift"]["energy"]


def test_variational_integrator_refusals():
    model = nhc.Scene.from_toml(OSCILLATOR).build("chetaev")
    with pytest.raises(nhc.SceneError, match="needs step=H"):
        model.simulate(t_end=1, integrator="variational")
    with pytest.raises(nhc.SceneError, match="ida or variational"):
        model.simulate(t_end=1, integrator="rk4", step=0.1)
    with pytest.raises(nhc.SceneError, match="fixed step of integrator='variational'"):
        model.simulate(t_end=1, step=0.1)
    with pytest.raises(nhc.SceneError, match="more than max_steps"):
        model.simulate(t_end=1, integrator="variational", step=1e-9)


def test_a_new_process_builds_an_interpreted_scene_from_the_cache(tmp_path):
    # Scene.build(backend="interpreted") in a new process takes the program the first process
    # stored (docs/interpreter.md, "The second run"): nothing derived or generated (derive_seconds
    # 0), the same numbers to the bit, and the compiled model's numbers too.
    import os
    import subprocess
    import sys

    script = (
        "import sys, nhc\n"
        "scene = nhc.Scene.from_toml(sys.argv[1])\n"
        "run = scene.build('chetaev', backend=sys.argv[2]).simulate(t_end=2.0, outputs=50)\n"
        "print(run.summary['derive_seconds'])\n"
        "print([x.hex() for x in run['x']])\n"
    )
    env = dict(os.environ, NHC_CACHE_DIR=str(tmp_path / "cache"))

    def build_in_a_new_process(backend):
        out = subprocess.run([sys.executable, "-c", script, OSCILLATOR, backend], env=env, check=True,
                             capture_output=True, text=True).stdout.splitlines()
        return float(out[0]), out[1]

    cold_derive, cold_x = build_in_a_new_process("interpreted")
    warm_derive, warm_x = build_in_a_new_process("interpreted")
    assert cold_derive > 0
    assert warm_derive == 0
    assert warm_x == cold_x
    assert build_in_a_new_process("auto") == (0.0, cold_x)
    assert build_in_a_new_process("compiled")[1] == cold_x
    with pytest.raises(ValueError, match="backend must be"):
        nhc.Scene.from_toml(OSCILLATOR).build("chetaev", backend="fast")
