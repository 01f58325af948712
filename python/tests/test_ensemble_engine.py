"""nhc ensemble runs each member through the one run engine (app::SceneRuns, app::simulate): the
scene's events, contacts (stop and slide) and sampled controller compose with the design as they
do with nhc simulate --set. Each member against an independent answer: the slip time of a rolling
cylinder under a growing torque, t = 3 mu m g r / (2 k) (docs/contacts.md eq. (5)); the landing
time of a thrown ball; the motion by hand of the interaction matrix (test_combinations.reference,
SciPy); and the same run made alone by nhc simulate --set (to 1e-12). The MPI path gives the
serial path's file (docs/ensemble.md, docs/combinations.md "nhc ensemble")."""
import csv
import os
import shutil
import subprocess

import numpy as np
import pytest

h5py = pytest.importorskip("h5py")

from test_combinations import reference, scene_text  # noqa: E402  (the matrix's system)
from test_parameter_numbers import CYLINDER, slip_time  # noqa: E402

OK, SINGULAR, FAILED, STOPPED = 1, 2, 3, 4


def nhc_command() -> str:
    program = os.environ.get("NHC_EXECUTABLE")
    if not program:
        pytest.skip("NHC_EXECUTABLE is not set (ctest sets it)")
    return program


def ensemble(path, *flags, cwd=None, prefix=()):
    return subprocess.run([*prefix, nhc_command(), "ensemble", str(path), *flags], capture_output=True, text=True,
                          cwd=cwd, timeout=600)


def text(values):
    return [v.decode() if isinstance(v, bytes) else str(v) for v in values]


def read(path):
    """The file's runs: design values, outcome codes, t_stop, message, events [(name, t)], final
    state and trajectories by state name."""
    with h5py.File(path, "r") as f:
        names = text(f["runs/state_names"][...])
        out = {
            "values": f["design/values"][...],
            "outcome": f["runs/outcome"][...].astype(int),
            "t_stop": f["runs/t_stop"][...],
            "message": text(f["runs/message"][...]),
            "events": [[(line.split(",")[0], float(line.split(",")[1])) for line in e.splitlines()]
                       for e in text(f["runs/events"][...])],
            "final": {n: f["runs/final_state"][:, i] for i, n in enumerate(names)},
        }
        if "trajectories" in f:
            out["t"] = f["trajectories/t"][...]
            out["y"] = {n: f["trajectories/y"][:, :, i] for i, n in enumerate(names)}
    return out


@pytest.mark.parametrize("on_slip", ["stop", "slide"])
def test_each_members_slip_is_the_closed_form_of_its_mu(on_slip, tmp_path):
    """--vary muT with mu = "muT": each member slips at 3 mu m g r / (2 k) of its own mu (to 1e-8);
    with on_slip = "stop" the slip ends it (outcome stopped, t_stop the slip, the message names
    it), with "slide" it slides on to t_end."""
    path = tmp_path / "cylinder.toml"
    path.write_text(CYLINDER + ('on_slip = "slide"\n' if on_slip == "slide" else ""))
    done = ensemble(path, "--vary", "muT=0.05:0.25:5", "--threads", "2", "-o", str(tmp_path / "e.h5"))
    assert done.returncode == 0, done.stderr
    r = read(tmp_path / "e.h5")
    mu = r["values"][:, 0]
    assert np.allclose(mu, np.linspace(0.05, 0.25, 5))
    for k in range(5):
        assert r["events"][k][0][0] == "floor.slip", r["events"][k]
        assert abs(r["events"][k][0][1] - slip_time(mu[k])) < 1e-8, (mu[k], r["events"][k])
    if on_slip == "stop":
        assert list(r["outcome"]) == [STOPPED] * 5, r["message"]
        assert np.max(np.abs(r["t_stop"] - slip_time(mu))) < 1e-8, r["t_stop"]
        assert all(m.startswith("stopped by event floor.slip at t = ") for m in r["message"]), r["message"]
        assert "0 ok, 5 ended by an event, 0 stopped at a singular point, 0 failed" in done.stdout, done.stdout
    else:
        assert list(r["outcome"]) == [OK] * 5 and np.all(r["t_stop"] == 4.0), r["message"]
        assert all(len(e) == 1 for e in r["events"]), r["events"]  # the torque grows: it slides on


BALL = """
name = "ball"
coordinates = ["y"]
lagrangian = "m/2*y'^2 - m*g*y"
[parameters]
m = 1.0
g = 9.81
c = 0.0
h = 2.0
[initial]
y = ["h", 0.0]
[simulate]
t_end = 3.0
rtol = 1e-10
atol = 1e-12
[events]
floor = { when = "y - c", direction = "down", action = "stop" }
"""


def test_each_members_stop_event_is_its_landing_time(tmp_path):
    """A ball thrown up at v0 from the height h (written through a parameter) under g stops at the
    level c (a threshold only the event reads): y = h + v0 t - g t^2/2 reaches c at
    t = (v0 + sqrt(v0^2 + 2 g (h - c))) / g for every member of a grid over g, c, h and y'(0); the
    rows before it are the parabola, the rows after it NaN."""
    path = tmp_path / "ball.toml"
    path.write_text(BALL)
    done = ensemble(path, "--vary", "g=5:15:3", "--vary", "c=0:1:2", "--vary", "h=1.5:2:2", "--vary", "y'(0)=0:2:2",
                    "--keep", "trajectories", "--outputs", "30", "-o", str(tmp_path / "e.h5"))
    assert done.returncode == 0, done.stderr
    r = read(tmp_path / "e.h5")
    assert len(r["outcome"]) == 24 and list(r["outcome"]) == [STOPPED] * 24, r["message"]
    g, c, h, v0 = r["values"].T
    landing = (v0 + np.sqrt(v0**2 + 2 * g * (h - c))) / g
    assert np.max(np.abs(r["t_stop"] - landing)) < 1e-8, (r["t_stop"], landing)
    assert [e[0][0] for e in r["events"]] == ["floor"] * 24
    assert np.max(np.abs(r["final"]["y"] - c)) < 1e-8
    assert np.max(np.abs(r["final"]["y'"] - (v0 - g * landing))) < 1e-7
    t = r["t"]
    for k in range(24):
        before = t < landing[k] - 1e-9
        parabola = h[k] + v0[k] * t[before] - g[k] * t[before] ** 2 / 2
        assert np.max(np.abs(r["y"]["y"][k, before] - parabola)) < 1e-8, k
        assert np.all(np.isnan(r["y"]["y"][k, t > landing[k] + 1e-9]))  # (g = 5, v0 = 2, h - c = 0.5: at t = 1)


# The matrix's cylinder (test_combinations): each feature with --vary k, the torque rate, which
# the motion by hand takes as its argument.
FEATURES = [{"events"}, {"contact stop"}, {"contact slide"}, {"controller"}, {"controller", "contact stop"},
            {"controller", "contact slide"}, {"events", "contact slide"}, {"controller", "events"}]
RATES = np.linspace(0.5, 1.5, 3)


def run_matrix_ensemble(f, tmp_path, *flags):
    path = tmp_path / "combination.toml"
    path.write_text(scene_text(f))
    outputs = [] if "controller" in f else ["--outputs", "25"]  # the scene's [simulate] outputs
    done = ensemble(path, "--vary", "k=0.5:1.5:3", "--keep", "trajectories", *outputs, *flags,
                    "-o", str(tmp_path / "e.h5"))
    assert done.returncode == 0, done.stderr
    return path, outputs, read(tmp_path / "e.h5")


@pytest.mark.parametrize("f", FEATURES, ids=lambda f: "+".join(sorted(f)))
def test_members_against_the_motion_by_hand(f, tmp_path):
    """Every member of --vary k against the motion by hand at its k: the rows at the output
    times (the controller's samples), the events met and where the member ended."""
    _, _, r = run_matrix_ensemble(f, tmp_path, "--threads", "2")
    tol = 2e-5 if "contact slide" in f else 1e-6
    for j, k in enumerate(RATES):
        rows, events = reference(f, k)
        assert abs(r["values"][j, 0] - k) < 1e-15
        for i, name in enumerate(["x", "x'", "th", "th'"], start=1):
            scale = max(1.0, np.max(np.abs(rows[:, i])))
            for n, t in enumerate(r["t"]):
                at = np.flatnonzero(np.abs(rows[:, 0] - t) < 1e-9)
                if len(at) and t <= rows[-1, 0]:
                    assert abs(r["y"][name][j, n] - rows[at[-1], i]) < tol * scale, (name, k, t)
                elif t > rows[-1, 0] + 1e-9:
                    assert np.isnan(r["y"][name][j, n]), (name, k, t)
            assert abs(r["final"][name][j] - rows[-1, i]) < tol * scale, (name, k)
        assert abs(r["t_stop"][j] - rows[-1, 0]) < 1e-6, (k, r["t_stop"][j], rows[-1, 0])
        assert [n for n, _ in r["events"][j]] == [n for n, _ in events], (k, r["events"][j], events)
        for (_, a), (_, b) in zip(r["events"][j], events):
            assert abs(a - b) < 1e-6
        stopped = any(n in ("fast", "floor.slip") and not ("contact slide" in f and n == "floor.slip")
                      for n, _ in events)
        assert r["outcome"][j] == (STOPPED if stopped else OK), (k, r["message"][j])


@pytest.mark.parametrize("f", [{"events", "contact slide"}, {"controller", "contact stop"}],
                         ids=lambda f: "+".join(sorted(f)))
def test_each_member_is_nhc_simulate_with_set(f, tmp_path):
    """A member is the run nhc simulate --set k=… makes: its rows at the output times, its last
    row and its events equal the simulated CSV's and event table's (to 1e-12)."""
    path, outputs, r = run_matrix_ensemble(f, tmp_path, "--threads", "2")
    for j, k in enumerate(r["values"][:, 0]):
        csv_path = tmp_path / f"k{j}.csv"
        done = subprocess.run([nhc_command(), "simulate", str(path), "--set", f"k={k!r}", *outputs,
                               "--backend", "compiled", "-o", str(csv_path)], capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stderr
        with open(csv_path) as stream:
            rows = list(csv.DictReader(stream))
        t = np.array([float(row["t"]) for row in rows])
        for name in r["y"]:
            if name not in rows[0]:
                continue
            column = np.array([float(row[name]) for row in rows])
            for n, time in enumerate(r["t"]):
                at = np.flatnonzero(t == time)
                if len(at):
                    assert abs(r["y"][name][j, n] - column[at[0]]) <= 1e-12 * max(1.0, abs(column[at[0]])), name
                else:
                    assert np.isnan(r["y"][name][j, n]) and time > t[-1], (name, time)
            assert abs(r["final"][name][j] - column[-1]) <= 1e-12 * max(1.0, abs(column[-1])), name
        assert r["t_stop"][j] == t[-1]
        with open(tmp_path / f"k{j}.events.csv") as stream:
            simulated = [(row["name"], float(row["t"])) for row in csv.DictReader(stream)]
        assert r["events"][j] == simulated, (r["events"][j], simulated)


def test_the_mpi_path_gives_the_serial_file(tmp_path):
    """mpirun -np 2 and one process with two threads write the same records for a scene with
    events, a sliding contact and a controller (timings and placement aside)."""
    mpirun = shutil.which("mpirun") or shutil.which("mpiexec")
    if not mpirun:
        pytest.skip("no mpirun")
    f = {"controller", "contact slide"}
    path = tmp_path / "combination.toml"
    path.write_text(scene_text(f))
    flags = ["--vary", "k=0.5:1.5:4", "--vary", "muT=0.15:0.3:2", "--keep", "trajectories"]
    serial = ensemble(path, *flags, "--threads", "2", "-o", str(tmp_path / "serial.h5"))
    assert serial.returncode == 0, serial.stderr
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    mpi = subprocess.run([mpirun, "--oversubscribe", "-np", "2", nhc_command(), "ensemble", str(path), *flags,
                          "-o", str(tmp_path / "mpi.h5")], capture_output=True, text=True, env=env, timeout=600)
    if "on 2 ranks" not in mpi.stdout:
        pytest.skip("nhc was built without MPI: " + mpi.stdout + mpi.stderr)
    assert mpi.returncode == 0, mpi.stderr
    ignored = {"runs/seconds", "runs/rank"}
    with h5py.File(tmp_path / "serial.h5", "r") as a, h5py.File(tmp_path / "mpi.h5", "r") as b:
        names = []
        a.visit(names.append)
        other = []
        b.visit(other.append)
        assert names == other
        for name in names:
            if isinstance(a[name], h5py.Dataset) and name not in ignored:
                assert np.array_equal(a[name][...], b[name][...], equal_nan=a[name].dtype.kind == "f"), name
        for key, value in a.attrs.items():
            if key not in ("ranks", "threads", "wall_seconds"):
                assert b.attrs[key] == value, key
    r = read(tmp_path / "mpi.h5")
    assert len(r["outcome"]) == 8 and any(len(e) > 0 for e in r["events"])


def test_what_the_runs_share_or_cannot_run_is_refused_in_words(tmp_path):
    """The members share their output times and tolerances: a varied parameter the controller's
    period is written through is refused at the flag, as --outputs under a controller (its samples
    are the rows) and model predictive control (its plans need IPOPT and a derivation per run)."""
    path = tmp_path / "combination.toml"
    path.write_text(scene_text({"controller", "events"}))
    done = ensemble(path, "--vary", "h=0.1:0.2:2", "-o", str(tmp_path / "e.h5"))
    assert done.returncode == 2 and "the scene's [controller] period" in done.stderr, done.stderr
    assert "written through 'h', which the runs of nhc ensemble share" in done.stderr
    done = ensemble(path, "--vary", "k=1:2:2", "--outputs", "10", "-o", str(tmp_path / "e.h5"))
    assert done.returncode == 2 and "--outputs: the scene's [controller] runs from sample to sample" in done.stderr
    pendulum = os.path.join(os.environ.get("NHC_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..")),
                            "examples", "wheeled_pendulum_mpc.toml")
    done = ensemble(pendulum, "--vary", "m=1:2:2", "-o", str(tmp_path / "e.h5"))
    assert done.returncode == 2 and "nhc ensemble does not run the scene's model predictive control" in done.stderr, \
        done.stderr
    assert not (tmp_path / "e.h5").exists()
