"""Long calls from Python: Ctrl-C ends them (KeyboardInterrupt) while they work, and symbolic work
is safe from several threads (python/src/symbolic_work.hpp)."""
import os
import signal
import threading
import time

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
"""


def interrupted_after(seconds, call):
    """call() with SIGINT sent to this process `seconds` after it starts, as Ctrl-C would: the
    seconds from the signal to KeyboardInterrupt (the call must raise it)."""
    sent = []

    def interrupt():
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(seconds, interrupt)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            call()
    finally:
        timer.cancel()
    assert sent, "the call ended before the signal"
    return time.monotonic() - sent[0]


def test_ctrl_c_stops_a_run_with_sensitivities_between_outputs():
    # One output interval over 10^5 time units (5.9 10^6 steps with their sensitivities: 75 s
    # uninterrupted on the machine this was written on). The stop request used to be asked only at outputs, so the signal waited for the
    # end of the run; now it is asked every 32 residual evaluations.
    model = nhc.Scene.from_toml(OSCILLATOR).build("chetaev")
    model.simulate(t_end=1, outputs=1, sensitivity=["x(0)"])  # the same call, short: it works
    waited = interrupted_after(0.3, lambda: model.simulate(t_end=1e5, outputs=1, sensitivity=["x(0)"],
                                                          max_steps=10**12))
    assert waited < 10.0  # minutes without the check; milliseconds with it


def test_ctrl_c_stops_a_build(source, tmp_path, monkeypatch):
    # The Whipple bicycle from a cold cache: derivation and generation (about half a second), then
    # the compiler (seconds). SIGINT 0.2 s in ends the build before anything is compiled (it took
    # the whole build, 8 s, before), and the compiler is never left running: no library in the cache.
    monkeypatch.setenv("NHC_CACHE_DIR", str(tmp_path / "cache"))
    scene = nhc.Scene.load(source / "examples/whipple/whipple_bicycle.toml")
    waited = interrupted_after(0.2, lambda: scene.build("chetaev"))
    assert waited < 10.0
    assert not [p for p in (tmp_path / "cache").rglob("*.so")]


def test_ctrl_c_stops_the_compiler(source, tmp_path, monkeypatch):
    # The same build with the signal during the compile (after the derivation, whose end the scene
    # cache's header marks): the compiler's process group is stopped, no library is kept.
    monkeypatch.setenv("NHC_CACHE_DIR", str(tmp_path / "cache"))
    scene = nhc.Scene.load(source / "examples/whipple/whipple_bicycle.toml")
    headers = []

    def watch():
        # The generated header is in the cache's temporary files once the compiler runs.
        while not headers:
            headers.extend(p for p in (tmp_path / "cache").rglob("*") if p.suffix in (".hpp", ".cpp", ".h"))
            time.sleep(0.01)
        os.kill(os.getpid(), signal.SIGINT)

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        scene.build("chetaev")
    assert headers
    assert not [p for p in (tmp_path / "cache").rglob("*.so")]
    assert time.monotonic() - started < 60.0


SECOND = """
name = "pendulum"
coordinates = ["th"]
lagrangian = "m*l^2*th'^2/2 + m*g*l*cos(th)"
[parameters]
m = 1.0
l = 0.5
g = 9.81
[initial]
th = [0.3, 0.0]
"""


def test_two_threads_derive_two_scenes():
    # GiNaC's reference counts and the intermediates' memo tables are not synchronised: symbolic
    # work holds the GIL. Each thread must get exactly what a lone derivation gives.
    expected = {text: (nhc.Scene.from_toml(text).derive("chetaev").text,
                       nhc.Scene.from_toml(text).analyze("chetaev").initial_point)
                for text in (OSCILLATOR, SECOND)}
    failures = []

    def work(text, rounds):
        try:
            for _ in range(rounds):
                scene = nhc.Scene.from_toml(text, set={})
                assert scene.derive("chetaev").text == expected[text][0]
                assert scene.analyze("chetaev").initial_point == pytest.approx(expected[text][1])
        except BaseException as e:  # noqa: B902 -- reported by the main thread
            failures.append(e)

    threads = [threading.Thread(target=work, args=(text, 100)) for text in (OSCILLATOR, SECOND, OSCILLATOR, SECOND)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not failures, failures


def test_runs_with_events_beside_derivations(tmp_path, monkeypatch):
    # A run lets the GIL go; its [events] expressions are lowered before (scene_events.cpp) and
    # any GiNaC work they still need takes the GIL back (nhc/long_work.hpp's symbolic lock), while
    # two other threads derive. x = cos(2 t): x (2 + sin x) vanishes at t = pi/4 + j pi/2.
    monkeypatch.setenv("NHC_CACHE_DIR", str(tmp_path / "cache"))
    text = OSCILLATOR + '[events]\nzero = { when = "x*(2 + sin(x))", direction = "any", action = "record" }\n'
    model = nhc.Scene.from_toml(text).build("chetaev")
    failures = []

    def run(rounds):
        try:
            for _ in range(rounds):
                times = [e.t for e in model.simulate(t_end=3, rtol=1e-10, atol=1e-12, outputs=3).events]
                assert times == pytest.approx([np.pi / 4, 3 * np.pi / 4], abs=1e-6)
        except BaseException as e:  # noqa: B902 -- reported by the main thread
            failures.append(e)

    def derive(rounds):
        try:
            for _ in range(rounds):
                nhc.Scene.from_toml(SECOND).derive("chetaev")
        except BaseException as e:  # noqa: B902 -- reported by the main thread
            failures.append(e)

    threads = [threading.Thread(target=run, args=(40,))] + [threading.Thread(target=derive, args=(40,)) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not failures, failures


def test_threads_run_while_a_build_waits_for_the_compiler(tmp_path, monkeypatch):
    # The GIL is let go while the compiler runs: a Python thread counts meanwhile, and a second
    # thread's derivation goes on beside the first thread's build.
    monkeypatch.setenv("NHC_CACHE_DIR", str(tmp_path / "cache"))
    scene = nhc.Scene.from_toml(OSCILLATOR.replace("k = 4.0", "k = 4.5"))
    results = {}
    builder = threading.Thread(target=lambda: results.setdefault("model", scene.build("chetaev")))
    builder.start()
    derived = 0
    while builder.is_alive():
        nhc.Scene.from_toml(SECOND).derive("chetaev")
        derived += 1
    builder.join()
    run = results["model"].simulate(t_end=1, outputs=10)
    assert np.max(np.abs(run["x"] - np.cos(np.sqrt(4.5) * run.t))) < 1e-6
    assert derived >= 1


RUNAWAY = """
name = "runaway"
coordinates = ["x", "y"]
lagrangian = '''(sin(x)+cos(y)+x'^-1)^12*(x+y'^-1)^-12*(y'+x)^9'''
[initial]
x = [0.1, 1.0]
y = [0.2, 0.5]
"""


def test_the_work_budget_stops_symbolic_work_with_the_stage_named():
    # The command line's --work-limit, from Python. The scene needs minutes of processor
    # time to derive (tests/fuzz/corpus/scene/slow_derivation_trig_sums_over_reciprocals.toml).
    assert nhc.work_limit() == 4.0
    scene = nhc.Scene.from_toml(RUNAWAY, path="runaway.toml")
    nhc.set_work_limit(0.5)
    try:
        with pytest.raises(nhc.SceneError, match=r"^runaway\.toml: error: deriving the equations took more than "
                                                  r"0\.5 s of processor time.*nhc\.set_work_limit"):
            scene.derive("chetaev")
        with pytest.raises(ValueError):
            nhc.set_work_limit(0)
    finally:
        nhc.set_work_limit(4.0)
    # The limit holds per call: the oscillator derives after the refusal.
    assert "x" in nhc.Scene.from_toml(OSCILLATOR).derive("chetaev").text
