"""nhc, the nonholonomic compiler, from Python (docs/python.md).

    import nhc
    scene = nhc.Scene.load("examples/rolling_disk.toml", set={"R": 0.4})
    eqs = scene.derive("chetaev")          # shown as LaTeX in Jupyter; eqs.text, eqs.json
    sym = eqs.to_sympy()                   # sym.residuals, sym.mass_matrix, sym.forcing (SymPy)
    info = scene.analyze("chetaev")        # info.index, info.dof, info.needed, info.initial_point
    model = scene.build("chetaev")         # derived, compiled (both caches), loaded
    run = model.simulate(t_end=10, rtol=1e-9, atol=1e-11, outputs=400)   # run.t, run["x"], run.summary
    lin = scene.linearize("chetaev", at={"th": 0, "ph'": 5})          # lin.A, lin.eigenvalues, lin.verdict
"""
from . import _nhc
from .errors import Error, HostError, MathError, SceneError
from .model import Event, Linearization, LinearizationAlong, Model, Mpc, Run, Sweep
from .compare import compare
from .scene import Analysis, Derivation, Scene
from .sympy_form import SympyEquations

__version__ = _nhc.__version__


def set_work_limit(seconds: float) -> None:
    """Sets the processor seconds of symbolic work (loading, deriving, analysing, building,
    linearizing) that one call may spend before it stops with nhc.SceneError naming the scene
    file and the stage: the command line's --work-limit (docs/python.md).

    :param seconds: a positive number of seconds (default 4)
    :raises ValueError: seconds is not a positive number."""
    _nhc._set_work_limit(seconds)


def work_limit() -> float:
    """The processor seconds of symbolic work one call may spend (set_work_limit)."""
    return _nhc._work_limit()


__all__ = ["Scene", "Derivation", "Analysis", "Model", "Mpc", "Run", "Event", "Linearization", "LinearizationAlong", "Sweep",
           "compare", "SympyEquations", "Error", "SceneError", "MathError", "HostError", "set_work_limit", "work_limit"]
