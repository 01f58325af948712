"""nhc.Scene.optimize against closed forms and its own rules (docs/optimize.md)."""
import math

import numpy as np
import pytest

import nhc


def test_heisenberg_loop_costs_two_pi_a_over_t(source):
    # The isoperimetric inequality: from (0, 0, 0) to (0, 0, a = 0.5) in T = 1 the least
    # 1/2 int (x'^2 + y'^2) dt is 2 pi a / T = pi, on a circle of radius sqrt(a/pi).
    run = nhc.Scene.load(source / "examples" / "heisenberg_optimal.toml").optimize(intervals=50)
    assert run.cost == pytest.approx(math.pi, rel=1e-6)
    x, y = run["x"], run["y"]
    r = np.hypot(x - x[:-1].mean(), y - y[:-1].mean())  # the last point is the first again
    assert np.max(np.abs(r - math.sqrt(0.5 / math.pi))) < 1e-4
    assert run.summary["status"] == "optimal"


def test_a_previous_optimum_is_a_guess_that_ends_in_a_few_iterations(source, tmp_path):
    scene = nhc.Scene.load(source / "examples" / "heisenberg_optimal.toml")
    first = scene.optimize()
    again = scene.optimize(guess=first)
    assert again.summary["iterations"] <= 3
    assert again.cost == pytest.approx(first.cost, rel=1e-9)
    csv = tmp_path / "first.csv"
    csv.write_text(",".join(first.columns) + "\n" + "\n".join(",".join(repr(v) for v in row) for row in first.to_numpy()) + "\n")
    assert scene.optimize(guess=csv).summary["iterations"] <= 3


def test_inputs_within_their_bounds(source):
    run = nhc.Scene.load(source / "examples" / "wheeled_pendulum_move.toml").optimize(intervals=30)
    assert np.all(np.abs(run["tau"]) <= 1.0)
    assert run["x"][-1] == pytest.approx(1.0) and run["theta"][-1] == pytest.approx(0.0, abs=1e-12)
    assert run.summary["problem"] == "chetaev"


def test_the_iteration_limit_raises_with_the_last_point(source):
    scene = nhc.Scene.load(source / "examples" / "heisenberg_optimal.toml")
    with pytest.raises(nhc.MathError, match="iteration limit") as caught:
        scene.optimize(max_iterations=2)
    assert len(caught.value.run) == 81 and caught.value.run.cost is not None


def test_bad_arguments_are_scene_errors_naming_them(source):
    scene = nhc.Scene.load(source / "examples" / "heisenberg_optimal.toml")
    with pytest.raises(nhc.SceneError, match="intervals: 0 is not a whole number"):
        scene.optimize(intervals=0)
    with pytest.raises(nhc.SceneError, match="hessian: 'bfgs' is neither exact nor limited-memory"):
        scene.optimize(hessian="bfgs")
