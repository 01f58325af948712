"""Scene.build and Model.simulate take the path of `nhc simulate` (app/nhc/app/preparation.hpp,
app::prepare_and_build): the model is derived and analysed once, and given initial values that miss a
hidden constraint are refused before anything is compiled, in the command line's words."""
import os
import re
import subprocess

import numpy as np
import pytest

import nhc
from nhc import _nhc


def nhc_command() -> str:
    """The nhc program of the build (NHC_EXECUTABLE, set by ctest)."""
    program = os.environ.get("NHC_EXECUTABLE")
    if not program:
        pytest.skip("NHC_EXECUTABLE is not set (ctest sets it)")
    return program


def appell_hamel_with_z(source, tmp_path, z):
    """examples/appell_hamel.toml with `z = <z>` in [initial]: z' = 0.559 misses the hidden
    constraint z' = sqrt(x'^2 + y'^2)/2 = 0.5590169944 by 1.7e-5."""
    text = (source / "examples" / "appell_hamel.toml").read_text()
    changed = re.sub(r"\nz = \[0\.0\]\n", f"\nz = {z}\n", text)
    assert changed != text
    path = tmp_path / "appell_hamel_z.toml"
    path.write_text(changed)
    return path


def test_build_derives_and_analyses_once(source, monkeypatch):
    monkeypatch.setenv("NHC_SCENE_CACHE", "off")  # the check is not taken from the scene cache
    scene = nhc.Scene.load(source / "examples" / "appell_hamel.toml")
    derived, analysed = _nhc._derive_model_calls(), _nhc._analyze_structure_calls()
    model = scene.build("chetaev")
    # The initial-point check's derivation and structure are what the build reduces from.
    assert (_nhc._derive_model_calls() - derived, _nhc._analyze_structure_calls() - analysed) == (1, 1)
    model.simulate(t_end=0.1, outputs=2)
    assert (_nhc._derive_model_calls() - derived, _nhc._analyze_structure_calls() - analysed) == (1, 1)


def test_inconsistent_initial_point_refused_as_on_the_command_line(source, tmp_path):
    path = appell_hamel_with_z(source, tmp_path, "[0.0, 0.559]")
    cli = subprocess.run([nhc_command(), "simulate", str(path), "-o", str(tmp_path / "out.csv")],
                         capture_output=True, text=True)
    assert cli.returncode == 3
    assert not (tmp_path / "out.csv").exists()
    lines = cli.stderr.splitlines()
    assert lines[0].startswith("nhc: error: ") and "hidden constraint f1" in lines[0]
    with pytest.raises(nhc.MathError) as refused:
        nhc.Scene.load(path).build()  # refused by the build, before any simulate
    # The same words (the command line prefixes each error line with "nhc: error: ").
    assert str(refused.value).splitlines()[0] == lines[0][len("nhc: error: "):]
    assert "nhc: error: " + str(refused.value) in cli.stderr
    # Given consistent values, the same scene builds.
    nhc.Scene.load(appell_hamel_with_z(source, tmp_path, "[0.0, 0.5590169944]")).build()


def test_drift_after_a_slide_is_measured_where_the_contact_rolls(source):
    """examples/sliding_cylinder.toml: friction takes energy while the cylinder slides, none once it
    rolls (t > v0/(3 mu g), docs/contacts.md eq. (6)); the rolling model's invariant and hidden
    constraint hold while it rolls, and the summary measures their drift there, as nhc simulate's."""
    m, v0 = 2.0, 3.0
    run = nhc.Scene.load(source / "examples" / "sliding_cylinder.toml").build("chetaev").simulate(outputs=20)
    rolling = run.t > run.events[0].t
    # Over the whole run the energy falls by m v0^2/6 (1/2 m v0^2 before, 1/3 m v0^2 rolling at 2 v0/3).
    energy = m * v0**2 / 3
    assert abs(run.summary["invariant_drift"]["energy"]) < 1e-9 * energy
    assert run.summary["hidden_drift"] < 1e-9
    assert np.count_nonzero(rolling) > 5
