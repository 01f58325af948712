"""nhc report runs every measured run through the one run engine (app::SceneRuns::run_at): a
scene's events and contacts end or switch each run as nhc simulate's, and --set moves a contact's
mu. Against closed forms (docs/combinations.md, "nhc report"): a ball dropped from h stops at the
level c at t = sqrt(2 (h - c) / g); a cylinder rolling under the torque k t slips at
t = 3 mu m g r / (2 k) (docs/contacts.md eq. (5)), its rolling motion x = k t^3 / (9 m r) up to
there the scene's [reference]."""
import csv
import math
import os
import subprocess

import pytest

from test_parameter_numbers import CYLINDER, G, K, M, R, slip_time  # noqa: E402


def nhc_command() -> str:
    program = os.environ.get("NHC_EXECUTABLE")
    if not program:
        pytest.skip("NHC_EXECUTABLE is not set (ctest sets it)")
    return program


def report(path, out, *flags):
    return subprocess.run([nhc_command(), "report", str(path), "--jacobian", "dense", "--projection", "off",
                           "--tolerances", "1e-5:1e-9", "--repeats", "1", *flags, "-o", str(out)],
                          capture_output=True, text=True, timeout=600)


def rows(out):
    with open(out / "workprec.csv") as stream:
        return list(csv.DictReader(stream))


BALL = """
name = "ball"
coordinates = ["y"]
lagrangian = "m/2*y'^2 - m*g*y"
[parameters]
m = 1.0
g = 9.81
c = 0.5
h = 2.0
[initial]
y = ["h", 0.0]
[simulate]
t_end = 3.0
[reference]
y = "h - g*t^2/2"
[events]
floor = { when = "y - c", direction = "down", action = "stop" }
"""


def test_each_run_of_a_report_stops_at_its_event(tmp_path):
    """Every tolerance's run stops at the event, t = sqrt(2 (h - c)/g), also with --set c and h:
    the error against [reference] is measured up to there."""
    path = tmp_path / "ball.toml"
    path.write_text(BALL)
    for flags, h, c in (([], 2.0, 0.5), (["--set", "c=1", "--set", "h=3"], 3.0, 1.0)):
        out = tmp_path / f"report{len(flags)}"
        done = report(path, out, *flags)
        assert done.returncode == 0, done.stderr
        landing = math.sqrt(2 * (h - c) / 9.81)
        measured = rows(out)
        assert len(measured) == 5
        for row in measured:
            assert abs(float(row["t_reached"]) - landing) < 1e-6, (row["rtol"], row["t_reached"], landing)
            assert float(row["error"]) < 1e-3 and row["status"] == "ok", row


def test_a_report_of_a_contact_slips_at_the_closed_form(tmp_path):
    """The rolling cylinder's contact (on_slip stop) ends every run at its slip, for the scene's
    mu and for --set muT=0.1 (mu = "muT"); up to there x = k t^3/(9 m r) ([reference])."""
    path = tmp_path / "cylinder.toml"
    path.write_text(CYLINDER.replace("[contacts.floor]", f'[reference]\nx = "k*t^3/(9*m*r)"\n'
                                     f'th = "k*t^3/(9*m*r^2)"\n[contacts.floor]'))
    for flags, mu in (([], 0.05), (["--set", "muT=0.1"], 0.1)):
        out = tmp_path / f"report{len(flags)}"
        done = report(path, out, *flags)
        assert done.returncode == 0, done.stderr
        for row in rows(out):
            assert abs(float(row["t_reached"]) - slip_time(mu)) < 1e-6, (row["rtol"], row["t_reached"])
            assert float(row["error"]) < 1e-4, row
    assert abs(slip_time(0.1) - 3 * 0.1 * M * G * R / (2 * K)) < 1e-15


def test_a_report_with_the_variational_integrator_refuses_events(tmp_path):
    path = tmp_path / "ball.toml"
    path.write_text(BALL)
    done = report(path, tmp_path / "out", "--integrators", "ida,variational")
    assert done.returncode == 2
    assert "--integrators variational takes fixed steps and locates no events; the scene's event 'floor'" \
        in done.stderr, done.stderr
    assert not (tmp_path / "out").exists()
