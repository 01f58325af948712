"""[contacts] in Python (docs/contacts.md): the force columns of a Run and the slip event, against
closed forms. The Whipple bicycle of examples/whipple/whipple_bicycle.toml running upright and
straight carries its static wheel loads (moments about the rear contact, eq. (7)) and needs no
friction; a uniform cylinder rolling down an incline needs the friction ratio tan(alpha)/3 with
the friction force up the slope (eq. (4)), and with mu below that it slips at t = 0."""
import math
import re

import numpy as np

import nhc

INCLINE = """name = "incline"
coordinates = ["s", "n", "th"]
lagrangian = "m/2*(s'^2 + n'^2) + m*r^2/4*th'^2 + m*g*(s*sin(alpha) - n*cos(alpha))"
constraints = ["n", "s' - r*th'"]
models = ["chetaev"]
[parameters]
m = 2.0
r = 0.3
g = 9.81
alpha = 0.5
[initial]
s = [0.0, 0.5]
n = [0.0, 0.0]
th = [0.0, "0.5/r"]
[simulate]
t_end = 1.0
outputs = 10
rtol = 1e-10
atol = 1e-12
[contacts.floor]
normal = "lambda1"
rolling = [2]
mu = MU
"""


def test_incline_ratio_and_slip_at_start():
    m, g, alpha = 2.0, 9.81, 0.5
    run = nhc.Scene.from_toml(INCLINE.replace("MU", "0.3")).build("chetaev").simulate()
    assert np.max(np.abs(run["floor.ratio"] - math.tan(alpha) / 3)) < 1e-10
    assert np.max(np.abs(run["floor.normal"] - m * g * math.cos(alpha))) < 1e-9
    assert np.max(np.abs(run["lambda2"] + m * g * math.sin(alpha) / 3)) < 1e-9  # up the slope
    assert np.all(run["floor.state"] == 1)
    assert run.events == []
    slipping = nhc.Scene.from_toml(INCLINE.replace("MU", "0.1")).build("chetaev").simulate()
    assert [(e.name, e.t) for e in slipping.events] == [("floor.slip", 0.0)]
    assert len(slipping.t) == 1


def test_bicycle_upright_carries_its_static_wheel_loads(source):
    text = (source / "examples" / "whipple" / "whipple_bicycle.toml").read_text()
    text = text.replace("phi = [0.0, 0.1]", "phi = [0.0, 0.0]")  # no lean kick: steady
    scene = nhc.Scene.from_toml(text)
    run = scene.build("chetaev").simulate(t_end=0.2, outputs=4)
    p = {k: float(v) for k, v in re.findall(r"^(\w+) = ([-0-9.e]+)\s", text, flags=re.M)}
    front = p["g"] * (p["mB"] * p["xB"] + p["mH"] * p["xH"] + p["mF"] * p["w"]) / p["w"]
    rear = p["g"] * (p["mR"] + p["mB"] + p["mH"] + p["mF"]) - front
    assert np.max(np.abs(run["front.normal"] - front)) < 1e-9 * front
    assert np.max(np.abs(run["rear.normal"] - rear)) < 1e-9 * rear
    assert np.max(np.abs(run["front.tangential"])) < 1e-9
    assert np.max(np.abs(run["rear.tangential"])) < 1e-9


def test_cylinder_launched_sliding_rolls_at_the_closed_form(source):
    """examples/sliding_cylinder.toml (on_slip = "slide"): rolling starts at t = v0/(3 mu g) with
    x' = 2 v0/3 (docs/contacts.md, eq. (6)); friction mu m g before, none after."""
    m, g, mu, v0 = 2.0, 9.81, 0.2, 3.0
    run = nhc.Scene.load(str(source / "examples" / "sliding_cylinder.toml")).build("chetaev").simulate(outputs=20)
    t_roll = v0 / (3 * mu * g)
    assert [e.name for e in run.events] == ["floor.stick"]
    assert abs(run.events[0].t - t_roll) < 1e-8
    sliding, rolling = run.t < t_roll - 1e-7, run.t > t_roll + 1e-7
    assert np.all(run["floor.state"][sliding] == 0) and np.all(run["floor.state"][rolling] == 1)
    assert np.max(np.abs(run["floor.tangential"][sliding] - mu * m * g)) < 1e-9
    assert np.max(np.abs(run["floor.tangential"][rolling])) < 1e-9
    assert np.max(np.abs(run["x'"][rolling] - 2 * v0 / 3)) < 1e-8
