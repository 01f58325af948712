"""The printed forms of a derivation depend on the scene only, not on what the process derived
before: the same scene derived after others, and from several threads, gives the same text, LaTeX
and JSON, byte for byte (docs/intermediates.md, "The same equations whatever ran before").

Compared within one process: the module runs in its host's address layout, which libginac's own
hash seeds follow, so two processes may order terms differently (the command line fixes its layout).
"""
import concurrent.futures

import nhc

SCENES = ["chaplygin_sleigh", "rolling_disk", "appell_hamel", "knife_edge", "wheeled_pendulum", "rattleback"]


def forms(source, name):
    d = nhc.Scene.load(source / "examples" / f"{name}.toml").derive("chetaev")
    return (d.text, d.latex, d.json)


def differing(name, got, expected):
    return [f"{name}: {form} differs" for form, g, e in zip(("text", "latex", "json"), got, expected) if g != e]


def test_a_scene_derived_after_others_prints_the_same(source):
    expected = {name: forms(source, name) for name in SCENES}
    problems = []
    for round_ in range(1, 4):
        for name in SCENES[round_:] + SCENES[:round_]:  # a different history before each scene
            problems += differing(name, forms(source, name), expected[name])
    assert problems == []


def test_threads_print_the_same(source):
    expected = {name: forms(source, name) for name in SCENES}
    with concurrent.futures.ThreadPoolExecutor(3) as pool:
        results = list(pool.map(lambda name: (name, forms(source, name)), SCENES * 3))
    problems = [p for name, got in results for p in differing(name, got, expected[name])]
    assert problems == []
