"""nhc, the nonholonomic compiler, from Python (docs/python.md).

    import nhc
    scene = nhc.Scene.load("examples/rolling_disk.toml", set={"R": 0.4})
    eqs = scene.derive("chetaev")          # shown as LaTeX in Jupyter; eqs.text, eqs.json
    info = scene.analyze("chetaev")        # info.index, info.dof, info.needed, info.initial_point
    model = scene.build("chetaev")         # derived, compiled (both caches), loaded
    run = model.simulate(t_end=10, rtol=1e-9, atol=1e-11, outputs=400)   # run.t, run["x"], run.summary
    lin = scene.linearize("chetaev", at={"th": 0, "ph'": 5})          # lin.A, lin.eigenvalues, lin.verdict
"""
from . import _nhc
from .errors import Error, HostError, MathError, SceneError
from .model import Linearization, Model, Run, Sweep
from .compare import compare
from .scene import Analysis, Derivation, Scene
from ._nhc import set_work_limit, work_limit

__version__ = _nhc.__version__
__all__ = ["Scene", "Derivation", "Analysis", "Model", "Run", "Linearization", "Sweep", "compare",
           "Error", "SceneError", "MathError", "HostError", "set_work_limit", "work_limit"]
