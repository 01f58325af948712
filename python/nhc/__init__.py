"""nhc, the nonholonomic compiler, from Python (docs/python.md).

    import nhc
    scene = nhc.Scene.load("examples/rolling_disk.toml", set={"R": 0.4})
    eqs = scene.derive("chetaev")          # shown as LaTeX in Jupyter; eqs.text, eqs.json
    info = scene.analyze("chetaev")        # info.index, info.dof, info.needed, info.initial_point
"""
from . import _nhc
from .errors import Error, HostError, MathError, SceneError
from .scene import Analysis, Derivation, Scene

__version__ = _nhc.__version__
__all__ = ["Scene", "Derivation", "Analysis", "Error", "SceneError", "MathError", "HostError"]
