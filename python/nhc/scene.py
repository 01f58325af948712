"""nhc.Scene: a scene file loaded, its models derived and analysed (docs/python.md)."""
import json as _json

from . import _nhc
import numpy as _np

from .errors import SceneError
from .model import Linearization, Model, Sweep


class Derivation:
    """One model's equations, as `nhc derive` writes them: `text`, `latex` (a standalone
    document), `latex_math` (the equations as math only, for MathJax), `json` (parsed: a dict).
    Jupyter shows the LaTeX equations."""

    def __init__(self, derived):
        self.model = derived.model
        self.text = derived.text
        self.latex = derived.latex
        self.latex_math = derived.latex_math
        self._json_text = derived.json

    @property
    def json(self):
        return _json.loads(self._json_text)

    def _repr_latex_(self):
        # Math only (align* blocks, headings as \text rows): MathJax renders math, not \section.
        return self.latex_math.strip()

    def __repr__(self):
        return self.text


class Analysis:
    """`nhc analyze` of one model: `index`, `dof`, `needed` (the initial values it takes),
    `initial_point` (name -> value at t0: those values, then the leading derivatives) and
    `condition` (of the system Jacobian there)."""

    def __init__(self, result):
        self.model = result["model"]
        self.index = result["index"]
        self.dof = result["dof"]
        self.needed = list(result["needed"])
        self.initial_point = dict(result["initial_point"])
        self.condition = result["condition"]

    def __repr__(self):
        return (f"Analysis(model={self.model!r}, index={self.index}, dof={self.dof}, "
                f"needed={self.needed!r})")


class Scene:
    """A scene (TOML) read and checked: `Scene.load(path, set={...})` or `Scene.from_toml(text)`.
    Bad input raises nhc.SceneError with the file, line and column."""

    def __init__(self, scene):
        self._scene = scene

    @classmethod
    def load(cls, path, set=None, expand=False):
        return cls(_nhc._Scene.load(str(path), dict(set or {}), expand))

    @classmethod
    def from_toml(cls, text, path="scene.toml", set=None, expand=False):
        return cls(_nhc._Scene.from_toml(text, str(path), dict(set or {}), expand))

    name = property(lambda self: self._scene.name)
    coordinates = property(lambda self: list(self._scene.coordinates))
    parameters = property(lambda self: dict(self._scene.parameters))
    inputs = property(lambda self: list(self._scene.inputs))
    models = property(lambda self: list(self._scene.models))

    def derive(self, model="chetaev"):
        return Derivation(self._scene.derive(model))

    def analyze(self, model="chetaev"):
        return Analysis(self._scene.analyze(model))

    def build(self, model="chetaev"):
        """The model derived, compiled (both caches) and loaded: an nhc.Model."""
        return Model(_nhc._build(self._scene, model))

    def linearize(self, model="chetaev", at=None):
        """Linear stability at the scene's [initial] with `at` values replaced (as --at)."""
        return Linearization(_nhc._linearize(self._scene, model, {k: float(v) for k, v in (at or {}).items()}))

    def sweep(self, model, name, values, at=None):
        """Linearizes at each of `values` (equally spaced, as np.linspace gives) of the parameter
        or initial value `name`, and refines where the verdict changes: an nhc.Sweep."""
        values = _np.asarray(values, dtype=float).ravel()
        if len(values) < 2 or not _np.all(_np.diff(values) > 0):
            raise SceneError("sweep values must be at least two, increasing")
        if _np.max(_np.abs(_np.diff(values) - (values[-1] - values[0]) / (len(values) - 1))) > 1e-9 * _np.max(_np.abs(values)):
            raise SceneError("sweep values must be equally spaced (np.linspace)")
        at = {k: float(v) for k, v in (at or {}).items()}
        return Sweep(name, _nhc._sweep(self._scene, model, name, values[0], values[-1], len(values), at))

    def __repr__(self):
        return f"Scene({self.name!r}, coordinates={self.coordinates!r})"
