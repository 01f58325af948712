"""Values from outside the scene: feedback laws written through [definitions] (in the
scene and from --input), --initial on every command that runs the model, the default end of a run
after a new t0, and Python's sampled controller taking [simulate] t_end. Each against an
independent path: the law written out, closed forms of the oscillator x'' = -k x, the Appell-Hamel
stop time."""
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import nhc


def nhc_command():
    """The nhc program of the build (NHC_EXECUTABLE, set by ctest)."""
    program = os.environ.get("NHC_EXECUTABLE")
    if not program:
        pytest.skip("NHC_EXECUTABLE is not set (ctest sets it)")
    return program


def command(*args, check=True):
    return subprocess.run([nhc_command(), *[str(a) for a in args]], capture_output=True, text=True, check=check)


def csv_table(path):
    """A CSV nhc wrote: {column: array}."""
    header = pathlib.Path(path).read_text().splitlines()[0].split(",")
    table = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: table[:, c] for c, name in enumerate(header)}


def same_run(a, b, tolerance=1e-12):
    assert a.keys() == b.keys()
    for name in a:
        scale = 1 + np.max(np.abs(a[name]))
        assert np.max(np.abs(a[name] - b[name])) <= tolerance * scale, name


# ---------------------------------------------------------------------------------------------
# Feedback laws through [definitions]

LAW_L = "0.7*psi + 11*th + 2.4*th' - 0.01*phL' + 0.33*phR'"
LAW_R = "-0.7*psi + 11*th + 2.4*th' + 0.33*phL' - 0.01*phR'"
TILT = "tilt = \"11*th + 2.4*th'\"\n"  # the shared part of both laws, as a definition
LAW_L_DEFINED = "0.7*psi + tilt - 0.01*phL' + 0.33*phR'"
LAW_R_DEFINED = "-0.7*psi + tilt + 0.33*phL' - 0.01*phR'"
RUN = ["--t-end", "1", "--outputs", "20", "--rtol", "1e-11", "--atol", "1e-13"]


def pendulum_text(source, definitions="", laws=("0", "0")):
    """examples/wheeled_pendulum.toml started from a 0.3 rad tilt, with `definitions` added to its
    [definitions] and `laws` as its [inputs]."""
    text = (source / "examples" / "wheeled_pendulum.toml").read_text().replace("th = [0.05, 0.0]", "th = [0.3, 0.0]")
    text = text.replace("[definitions]\n", "[definitions]\n" + definitions, 1)
    return text.replace('TL = "0"', f'TL = "{laws[0]}"').replace('TR = "0"', f'TR = "{laws[1]}"')


def test_a_law_through_a_definition_is_the_law_written_out(source, tmp_path):
    written = tmp_path / "written.toml"
    written.write_text(pendulum_text(source, laws=(LAW_L, LAW_R)))
    defined = tmp_path / "defined.toml"
    defined.write_text(pendulum_text(source, TILT, (LAW_L_DEFINED, LAW_R_DEFINED)))
    open_loop = tmp_path / "open.toml"  # the definition there, the laws from --input
    open_loop.write_text(pendulum_text(source, TILT))
    command("simulate", written, *RUN, "-o", tmp_path / "written.csv")
    command("simulate", defined, *RUN, "-o", tmp_path / "defined.csv")
    command("simulate", open_loop, *RUN, "--input", f"TL={LAW_L_DEFINED}", "--input", f"TR={LAW_R_DEFINED}",
        "-o", tmp_path / "flag.csv")
    a = csv_table(tmp_path / "written.csv")
    assert abs(a["th"][-1]) < 0.05 < abs(a["th"][0])  # the law holds the pendulum up
    same_run(a, csv_table(tmp_path / "defined.csv"))
    same_run(a, csv_table(tmp_path / "flag.csv"))
    # Python reads the scene's laws the same way.
    run = nhc.Scene.load(defined).build().simulate(t_end=1, outputs=20, rtol=1e-11, atol=1e-13)
    for name in a:
        if name in run:
            assert np.max(np.abs(a[name] - run[name])) <= 1e-12 * (1 + np.max(np.abs(a[name]))), name


def test_a_signal_of_t_through_a_definition_is_the_signal_written_out(source, tmp_path):
    signal = "0.02*sin(3*t)"
    written = tmp_path / "written.toml"
    written.write_text(pendulum_text(source, laws=(signal, "0")))
    defined = tmp_path / "defined.toml"
    defined.write_text(pendulum_text(source, 'w3 = "3*t"\n', ("0.02*sin(w3)", "0")))
    command("simulate", written, *RUN, "-o", tmp_path / "written.csv")
    command("simulate", defined, *RUN, "-o", tmp_path / "defined.csv")
    command("simulate", defined, *RUN, "--input", "TR=0.02*sin(w3)", "-o", tmp_path / "flag.csv")
    command("simulate", written, *RUN, "--input", f"TR={signal}", "-o", tmp_path / "both.csv")
    a = csv_table(tmp_path / "written.csv")
    same_run(a, csv_table(tmp_path / "defined.csv"))
    same_run(csv_table(tmp_path / "both.csv"), csv_table(tmp_path / "flag.csv"))


def test_a_law_through_a_definition_is_refused_where_the_law_written_out_is(source, tmp_path):
    # An acceleration reached through a definition is an algebraic loop (the input drives it); an
    # input reached through one is another input's law in this one, whatever the entries' order.
    for definitions, laws, words in (
            ("acc = \"th''\"\n", ("acc", "0"), "algebraic loop"),
            ('other = "2*TR"\n', ("th + other", "0"), "uses input 'TR' through a definition"),
            ('other = "2*TL"\n', ("th'", "th + other"), "uses input 'TL' through a definition")):
        scene = tmp_path / "bad.toml"
        scene.write_text(pendulum_text(source, definitions, laws))
        refused = command("simulate", scene, "-o", tmp_path / "bad.csv", check=False)
        assert refused.returncode == 2 and words in refused.stderr, refused.stderr
        assert "bad.toml:" in refused.stderr and not (tmp_path / "bad.csv").exists()
    scene = tmp_path / "open.toml"
    scene.write_text(pendulum_text(source, "acc = \"th''\"\n"))
    refused = command("simulate", scene, "--input", "TL=2*acc", check=False)
    errors = [line for line in refused.stderr.splitlines() if "error" in line]  # beside the unused-definition warning
    assert refused.returncode == 2 and len(errors) == 1, refused.stderr
    assert errors[0].startswith("--input: error: TL=2*acc: ") and "algebraic loop" in errors[0]
    # A name that is no definition stays the signal reader's to judge.
    refused = command("simulate", scene, "--input", "TL=2*nothing", check=False)
    assert refused.returncode == 2 and "nothing" in refused.stderr and "--input" in refused.stderr


# ---------------------------------------------------------------------------------------------
# --initial on every command that runs the model

OSCILLATOR = """
name = "oscillator"
coordinates = ["x"]
lagrangian = "x'^2/2 - k*x^2/2"
[parameters]
k = 4.0
[initial]
x = [1.0, 0.0]
"""


def oscillator(tmp_path, extra=""):
    path = tmp_path / "oscillator.toml"
    path.write_text(OSCILLATOR + extra)
    return path


def test_a_new_t0_moves_the_default_end_of_the_run(tmp_path):
    # Without [simulate] a run lasts 1 from t0: from the t0 given, on the command line and in Python.
    scene = oscillator(tmp_path)
    command("simulate", scene, "--initial", "t0=2", "--initial", "x'=0.5", "--outputs", "4", "-o", tmp_path / "a.csv")
    a = csv_table(tmp_path / "a.csv")
    assert list(a["t"]) == [2.0, 2.25, 2.5, 2.75, 3.0]
    # x = cos(2 (t - t0)) + 0.25 sin(2 (t - t0)) from x = 1, x' = 0.5 at t0.
    s = a["t"] - 2
    assert np.max(np.abs(a["x"] - (np.cos(2 * s) + 0.25 * np.sin(2 * s)))) < 1e-6
    run = nhc.Scene.load(scene).build().simulate(t0=2.0, outputs=4)
    assert list(run.t) == [2.0, 2.25, 2.5, 2.75, 3.0]
    # A t_end the scene gives stays where it is.
    fixed = oscillator(tmp_path, "[simulate]\nt_end = 4.0\n")
    command("simulate", fixed, "--initial", "t0=2", "--outputs", "4", "-o", tmp_path / "b.csv")
    assert csv_table(tmp_path / "b.csv")["t"][-1] == 4.0
    assert nhc.Scene.load(fixed).build().simulate(t0=2.0, outputs=4).t[-1] == 4.0


def test_initial_flag_messages_name_the_flag_once(tmp_path):
    scene = oscillator(tmp_path)
    for flag, message in (
            ("x=abc", "--initial: error: x=abc: 'abc' is not a number"),
            ("x", "--initial: error: x: expected NAME=VALUE"),
            ("x=inf", "--initial: error: x=inf: inf is not a finite number"),
            ("zz=1", "--initial: error: zz=1: 'zz' is neither t0, a coordinate nor a multiplier of the scene "
                     "(coordinates: x)")):
        for words in (["simulate"], ["report", "-q"], ["connect", "--to", "x=0", "--t-end", "1"]):
            refused = command(*words, scene, "--initial", flag, "-o", tmp_path / "out", check=False)
            assert refused.returncode == 2, (words, refused.stderr)
            assert refused.stderr.startswith(message), (words, refused.stderr)
            assert refused.stderr.count("\n") == 1 and refused.stderr.count("--initial") == 1, refused.stderr
            assert not (tmp_path / "out").exists()
    with pytest.raises(nhc.SceneError, match=r"^initial: error: zz = 1: 'zz' is neither"):
        nhc.Scene.load(scene).build().simulate(initial={"zz": 1.0})
    with pytest.raises(nhc.SceneError, match=r"^t0: error: nan is not a finite number"):
        nhc.Scene.load(scene).build().simulate(t0=float("nan"))


def test_report_starts_from_the_initial_flag(tmp_path):
    scene = oscillator(tmp_path)
    out = tmp_path / "report"
    command("report", scene, "--initial", "t0=0.5", "--initial", "x=2", "--tolerances", "1e-5:1e-6", "--jacobian",
        "dense", "--projection", "off", "--outputs", "10", "-q", "-o", out)
    text = (out / "report.md").read_text()
    assert "- t from 0.5 to 1.5;" in text  # the default end follows the new t0
    assert "- initial values set (as if written in [initial]): `t0=0.5` `x=2`" in text
    # The scene's [reference] x = cos 2t is the motion from its own x = 1: from x = 2 the error is
    # measured against a reference run (2 cos 2t against the closed form would be an error of 1).
    scene = oscillator(tmp_path, '[reference]\nx = "cos(2*t)"\n')
    for initial, source in (([], "reference"), (["--initial", "x=2"], "reference run")):
        out = tmp_path / f"report{len(initial)}"
        command("report", scene, *initial, "--tolerances", "1e-6", "--jacobian", "dense", "--projection", "off",
                "--outputs", "10", "-q", "-o", out)
        rows = (out / "workprec.csv").read_text().splitlines()
        header, row = rows[0].split(","), rows[1].split(",")
        assert row[header.index("error_source")] == source
        assert float(row[header.index("error")]) < 1e-4


def test_compare_starts_every_model_from_the_initial_flag(tmp_path):
    scene = oscillator(tmp_path)
    out = tmp_path / "compare"
    command("compare", scene, "--initial", "x=2", "--initial", "x'=1", "--t-end", "1", "--outputs", "10", "-o", out)
    tables = list(out.glob("*.csv"))
    assert tables
    for table in tables:
        a = csv_table(table)
        assert a["x"][0] == 2.0 and a["x'"][0] == 1.0
        assert abs(a["x"][-1] - (2 * math.cos(2) + 0.5 * math.sin(2))) < 1e-6  # x = 2 cos 2t + sin(2t)/2
    assert "--initial x=2 --initial x'=1" in (out / "compare.md").read_text()


def test_connect_starts_from_the_initial_flag(tmp_path):
    # x(0) = 2 from --initial, x'(0) free, x(1) = 0: 2 cos 2 + x'(0) sin(2)/2 = 0.
    scene = oscillator(tmp_path, "")
    scene.write_text(OSCILLATOR.replace("x = [1.0, 0.0]", "x = [1.0]"))
    command("connect", scene, "--initial", "x=2", "--to", "x=0", "--t-end", "1", "--outputs", "10",
        "-o", tmp_path / "c.csv")
    a = csv_table(tmp_path / "c.csv")
    assert a["x"][0] == 2.0
    assert abs(a["x'"][0] - (-4 * math.cos(2) / math.sin(2))) < 1e-6
    # A value given with --initial is not free.
    refused = command("connect", scene, "--initial", "x=2", "--initial", "x'=0", "--free", "x'(0)", "--to", "x=0",
                  "--t-end", "1", check=False)
    assert refused.returncode == 2
    assert refused.stderr.startswith("--initial: error: x'=0: x'(0) is given here, so it cannot be free"), refused.stderr


# ---------------------------------------------------------------------------------------------
# Python's sampled controller takes the scene's [simulate] t_end

DRIVEN = """
name = "driven"
coordinates = ["x"]
lagrangian = "x'^2/2"
[inputs]
u = "0"
[forces]
x = "u"
[initial]
x = [0.0, 0.0]
"""


def test_a_sampled_controller_without_t_end_runs_to_the_scenes_t_end(tmp_path):
    # x'' = u held at 1 over each sample: x = t^2/2 exactly; the run ends where [simulate] says,
    # else 1 after t0 (also a t0 given here).
    calls = []

    def controller(t, y, state):
        calls.append(t)
        return [1.0], state

    model = nhc.Scene.from_toml(DRIVEN + "[simulate]\nt_end = 0.5\n").build()
    run = model.simulate(controller=controller, period=0.1, rtol=1e-10, atol=1e-12)
    assert len(run) == 6 and abs(run.t[-1] - 0.5) < 1e-12 and len(calls) == 6  # the last sample too
    assert np.max(np.abs(run["x"] - run.t**2 / 2)) < 1e-8
    run = nhc.Scene.from_toml(DRIVEN).build().simulate(controller=controller, period=0.25, t0=2.0)
    assert len(run) == 5 and run.t[0] == 2.0 and abs(run.t[-1] - 3.0) < 1e-12


def test_a_t0_after_the_scenes_t_end_asks_for_t_end(tmp_path):
    scene = oscillator(tmp_path, "[simulate]\nt_end = 1.0\n")
    refused = command("simulate", scene, "--initial", "t0=2", check=False)
    assert refused.returncode == 2
    assert "error: the scene's [simulate] t_end 1 is not after t0 = 2: give --t-end" in refused.stderr, refused.stderr
    with pytest.raises(nhc.SceneError, match=r"t_end 1 is not after t0 = 2: give t_end"):
        nhc.Scene.load(scene).build().simulate(t0=2.0)
    command("simulate", scene, "--initial", "t0=2", "--t-end", "2.5", "-o", tmp_path / "a.csv")
    assert csv_table(tmp_path / "a.csv")["t"][-1] == 2.5


def test_animate_starts_from_the_initial_flag(source, tmp_path):
    out = tmp_path / "page"
    command("animate", source / "examples" / "rolling_disk.toml", "--initial", "t0=0.5", "--outputs", "4", "-o", out)
    assert '"t":[0.5,1.625,2.75,3.875,5]' in (out / "index.html").read_text()  # [simulate] t_end = 5 stays
