"""A run's result depends on its scene alone, not on the scenes run before it in the same
process: scenes with a sliding contact, a stopping contact, events, a controller and none of
these, run one after another in several orders in one process, each give the result of the same
scene run alone in a fresh process (the arrays to 1e-12, the same events). The pair that once
differed: the falling disk with its events, then the cylinder whose contact slides (its sliding
model lost the friction torque on th)."""
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import nhc
import test_combinations as combinations
import test_events as event_tests

SOURCE = pathlib.Path(__file__).resolve().parents[2]

SCENES = {
    "slide": combinations.scene_text({"contact slide"}),
    "stop": combinations.scene_text({"contact stop"}),
    "events": combinations.scene_text({"events"}),
    "controller": combinations.scene_text({"controller"}),
    "plain": combinations.scene_text(set()),
    "disk": event_tests.falling_disk(SOURCE),
}


def run(name):
    """(columns, events) of the scene `name` simulated with its own settings (the disk's: 2 s)."""
    model = nhc.Scene.from_toml(SCENES[name]).build("chetaev")
    result = model.simulate(t_end=2.0, outputs=40) if name == "disk" else model.simulate()
    return ({c: np.asarray(result[c], dtype=float) for c in result.columns},
            [(e.name, e.t) for e in result.events])


def in_child(order, out, poisoned=False):
    """[run(name) for name in order] in a fresh process (this file as a script). Poisoned: glibc
    fills every freed block (no thread cache, so that each free is filled), so that what a scene
    reads of memory freed before shows at once, whatever the allocator happened to reuse."""
    env = dict(os.environ)
    if poisoned:
        env["GLIBC_TUNABLES"] = "glibc.malloc.tcache_count=0:glibc.malloc.perturb=165"
    subprocess.run([sys.executable, __file__, ",".join(order), str(out)], check=True, cwd=out.parent, env=env)
    results = []
    with np.load(out) as data:
        for i in range(len(order)):
            columns = {k.split(":", 2)[2]: data[k] for k in data.files if k.startswith(f"{i}:c:")}
            events = list(zip(data[f"{i}:event_names"].tolist(), data[f"{i}:event_times"].tolist()))
            results.append((columns, events))
    return results


def same(name, got, expected):
    columns, events = got
    want_columns, want_events = expected
    assert sorted(columns) == sorted(want_columns), name
    for c, values in want_columns.items():
        assert columns[c].shape == values.shape, (name, c)
        assert np.max(np.abs(columns[c] - values), initial=0.0) <= 1e-12, (name, c)
    assert [e[0] for e in events] == [e[0] for e in want_events], name
    assert all(abs(a[1] - b[1]) <= 1e-12 for a, b in zip(events, want_events)), name


@pytest.fixture(scope="module")
def fresh(tmp_path_factory):
    directory = tmp_path_factory.mktemp("alone")
    return {name: in_child([name], directory / f"{name}.npz")[0] for name in SCENES}


ORDERS = {
    "disk-then-slide": ["disk", "slide"],
    "forward": list(SCENES),
    "backward": list(reversed(SCENES)),
    "interleaved": ["slide", "events", "disk", "stop", "slide", "controller", "plain", "disk", "slide"],
}


@pytest.mark.parametrize("order", ORDERS.values(), ids=ORDERS.keys())
def test_a_result_does_not_depend_on_the_scenes_run_before(order, fresh):
    for name in order:
        same(name, run(name), fresh[name])


@pytest.mark.parametrize("order", ORDERS.values(), ids=ORDERS.keys())
def test_a_result_does_not_depend_on_freed_memory(order, fresh, tmp_path):
    for name, result in zip(order, in_child(order, tmp_path / "poisoned.npz", poisoned=True)):
        same(name, result, fresh[name])


@pytest.mark.parametrize("name", ["slide", "stop", "events", "controller"])
def test_the_command_line_does_not_read_freed_memory(name, tmp_path):
    """One nhc process, one scene: its CSV is byte for byte the same with freed memory poisoned."""
    scene = tmp_path / f"{name}.toml"
    scene.write_text(SCENES[name])
    outputs = []
    for label, tunables in [("plain", None), ("poisoned", "glibc.malloc.tcache_count=0:glibc.malloc.perturb=165")]:
        env = dict(os.environ)
        env.pop("GLIBC_TUNABLES", None)
        if tunables:
            env["GLIBC_TUNABLES"] = tunables
        out = tmp_path / f"{label}.csv"
        done = subprocess.run([combinations.nhc_command(), "simulate", str(scene), "-o", str(out)], env=env,
                              capture_output=True, text=True, cwd=tmp_path)
        assert done.returncode == 0, done.stderr
        outputs.append(out.read_bytes())
    assert outputs[0] == outputs[1]


def test_the_sliding_cylinder_alone_is_right(fresh):
    """The reference the orders are held to is the motion found by hand (SciPy), not only nhc's."""
    combinations.check_against_reference({"contact slide"}, *fresh["slide"])


def test_the_falling_disk_then_the_sliding_cylinder(source, tmp_path):
    """The two tests as the suite once ran them in one process; the second failed (θ 13.66
    where SciPy's reference has 10.13)."""
    (tmp_path / "disk").mkdir()
    (tmp_path / "slide").mkdir()
    event_tests.test_rolling_disk_lean_event_matches_an_independent_model(source, tmp_path / "disk")
    combinations.test_pair("contact slide", "Python", "works", tmp_path / "slide")


if __name__ == "__main__":
    saved = {}
    for i, name in enumerate(sys.argv[1].split(",")):
        columns, events = run(name)
        saved.update({f"{i}:c:{k}": v for k, v in columns.items()})
        saved[f"{i}:event_names"] = np.array([e[0] for e in events], dtype=str)
        saved[f"{i}:event_times"] = np.array([e[1] for e in events], dtype=float)
    np.savez(sys.argv[2], **saved)
