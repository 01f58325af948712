"""Events and steps at their edges in Python (docs/events.md), against closed forms: max_step= and
initial_step= set IDA's steps of x'' = A sin(w t), whose closed form from rest is
x = A t/w - A sin(w t)/w^2, and a long run at tight tolerances starts; two crossings of x = sin t
1 ms apart are both found."""
import math

import numpy as np

import nhc

FORCED = """name = "forced"
coordinates = ["x"]
lagrangian = "x'^2/2"
[parameters]
A = 2.0
w = 0.5
[forces]
x = "A*sin(w*t)"
[initial]
x = [0.0, 0.0]
[simulate]
rtol = 1e-10
atol = 1e-12
"""

SINE = """name = "sine"
coordinates = ["x"]
lagrangian = "x'^2/2 - x^2/2"
[parameters]
A = 1.0
[initial]
x = [0.0, "A"]
[simulate]
t_end = 3.0
"""


def test_max_step_and_initial_step():
    A, w = 2.0, 0.5
    model = nhc.Scene.from_toml(FORCED).build("chetaev")
    run = model.simulate(t_end=10, max_step=0.01, initial_step=1e-6)
    assert run.summary["steps"] >= 1000  # 10 / 0.01
    exact = A * run.t / w - A * np.sin(w * run.t) / w**2
    assert np.max(np.abs(run["x"] - exact)) < 1e-7
    long = model.simulate(t_end=1e3)  # the first step from the first output time, not t_end
    exact = A * long.t / w - A * np.sin(w * long.t) / w**2
    assert np.max(np.abs(long["x"] - exact)) < 1e-5 * np.max(np.abs(exact))


def test_two_crossings_one_millisecond_apart():
    d = 5e-4
    scene = SINE + f'[events]\npeak = {{ when = "x - {math.cos(d)!r}", action = "record" }}\n'
    run = nhc.Scene.from_toml(scene).build("chetaev").simulate(outputs=3)
    assert [e.name for e in run.events] == ["peak", "peak"]
    # one on each side of the top, where the closed form sin t is at the level to the solution's error
    assert run.events[0].t < math.pi / 2 < run.events[1].t
    assert all(abs(math.sin(e.t) - math.cos(d)) < 3e-7 for e in run.events)
