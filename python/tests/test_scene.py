"""nhc.Scene: load, derive, analyze and the exceptions, each against an independent answer."""
import json
import math
import re

import pytest

import nhc

PENDULUM = """
name = "pendulum"
coordinates = ["th"]
lagrangian = "m*l^2*th'^2/2 + m*g*l*cos(th)"
[parameters]
m = 2.0
l = 0.5
g = 9.81
[initial]
th = [0.3, 0.0]
"""


def test_analyze_gives_the_closed_form_acceleration_at_t0():
    # m l^2 th'' = -m g l sin(th): th'' = -(g/l) sin(th).
    info = nhc.Scene.from_toml(PENDULUM).analyze("chetaev")
    assert info.index == 0
    assert info.dof == 2
    assert info.needed == ["th", "th'"]
    assert info.initial_point["th''"] == pytest.approx(-(9.81 / 0.5) * math.sin(0.3), rel=1e-12)


def test_set_replaces_a_parameter():
    info = nhc.Scene.from_toml(PENDULUM, set={"g": 1.62}).analyze("chetaev")
    assert info.initial_point["th''"] == pytest.approx(-(1.62 / 0.5) * math.sin(0.3), rel=1e-12)
    with pytest.raises(nhc.SceneError, match="'G' is not a parameter of the scene"):
        nhc.Scene.from_toml(PENDULUM, set={"G": 1.0})


def test_derive_json_evaluates_to_the_hand_derived_residual():
    # R_th = -m l^2 th'' - m g l sin(th), evaluated from the JSON's text at a point.
    eqs = nhc.Scene.from_toml(PENDULUM).derive("chetaev")
    text = eqs.json["models"]["chetaev"]["equations"][0]
    values = {"th": 0.7, "th_d1": 0.4, "th_d2": -1.3, "m": 2.0, "l": 0.5, "g": 9.81}
    python = text.replace("^", "**")
    got = eval(python, {"sin": math.sin, "cos": math.cos}, values)
    want = -2.0 * 0.25 * -1.3 - 2.0 * 9.81 * 0.5 * math.sin(0.7)
    assert got == pytest.approx(want, rel=1e-12)
    assert "\\begin{align" in eqs._repr_latex_()
    # Math only: MathJax shows \section and \texttt as raw text, so the LaTeX for Jupyter holds no document commands.
    for raw in ("\\section", "\\subsection", "\\texttt", "\\documentclass"):
        assert raw not in eqs._repr_latex_()
    assert "R_{\\theta}" in eqs._repr_latex_() or "R_{\\mathrm{th}}" in eqs._repr_latex_()
    assert eqs.json["models"]["chetaev"]["equation_names"] == ["R_th"]
    assert "R_th" in eqs.text


def test_scene_properties(source):
    scene = nhc.Scene.load(source / "examples" / "rolling_disk.toml", set={"r": 0.4})
    assert scene.name == "rolling_disk"
    assert scene.coordinates == ["x", "y", "psi", "phi", "ph"]
    assert scene.parameters["r"] == 0.4
    assert "chetaev" in scene.models


def test_bad_scenes_raise_scene_error_at_their_line(source):
    # The bad-input corpus states where each error is (`# expect: LINE:COLUMN`).
    cases = sorted((source / "tests" / "bad").glob("*.toml"))
    assert len(cases) > 100
    for path in cases:
        expect = re.match(rb"#\s*expect:\s*(\d+):(\d+)", path.read_bytes().splitlines()[0])
        with pytest.raises(nhc.Error) as caught:
            scene = nhc.Scene.load(path)
            scene.analyze(scene.models[0] if "chetaev" not in scene.models else "chetaev")
        error = caught.value
        assert isinstance(error, nhc.SceneError), f"{path.name}: {type(error).__name__}: {error}"
        assert (error.line, error.column) == (int(expect.group(1)), int(expect.group(2))), f"{path.name}: {error}"
        assert str(error).startswith(f"{path}:{error.line}:{error.column}: error: ")


def test_a_model_that_does_not_apply_is_a_math_error():
    # Suslov's model without `dependent` is bad input; an unknown model name too.
    with pytest.raises(nhc.SceneError, match="unknown model"):
        nhc.Scene.from_toml(PENDULUM).derive("lagrange")


def test_latex_prints_multi_letter_definitions_upright(source):
    # A definition named Tb reads as T times b unless set upright, in its own line
    # and inside d/dt dT/dpsi'.
    latex = nhc.Scene.load(source / "examples/wheeled_pendulum.toml").derive("chetaev")._repr_latex_()
    assert "\\frac{d}{dt}\\frac{\\partial \\mathrm{Tb}}{\\partial \\dot{\\psi}}" in latex
    assert "\\mathrm{Tb} &=" in latex
    assert "\\partial Tb" not in latex
