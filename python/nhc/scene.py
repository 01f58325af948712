"""nhc.Scene: a scene file loaded, its models derived and analysed (docs/python.md)."""
from __future__ import annotations

import json as _json
import os as _os
import re as _re
from typing import Any, Dict, List, Mapping, Optional, Sequence
from typing import cast as _cast

import numpy.typing as _npt

from . import _nhc
import numpy as _np

from .errors import MathError, SceneError
from .model import Linearization, Model, Run, Sweep


class Derivation:
    """One model's equations, as `nhc derive` writes them: `text`, `latex` (a standalone
    document), `latex_math` (the equations as math only, for MathJax), `json` (parsed: a dict).
    Jupyter shows the LaTeX equations."""

    def __init__(self, derived: _nhc._Derivation, scene: Optional[_nhc._Scene] = None) -> None:
        self._scene = scene
        self.model = derived.model
        self.text = derived.text
        self.latex = derived.latex
        self.latex_math = derived.latex_math
        self._json_text = derived.json

    @property
    def json(self) -> Dict[str, Any]:
        """The ``--format json`` form, parsed: ``{"scene", "parameters", "symbols", "models"}``."""
        return _cast(Dict[str, Any], _json.loads(self._json_text))

    def to_sympy(self, speeds: Optional[List[str]] = None) -> Any:
        """The equations as SymPy objects (nhc.sympy_form.SympyEquations): ``.residuals``,
        ``.definitions``, and for the chetaev and holder models with constraints linear in the
        velocities the multiplier-free form ``.speeds``, ``.mass_matrix`` (M_r), ``.forcing``
        (f_r), ``.dependent_speeds`` and ``.multipliers`` (docs/reduced-form.md).

        :param speeds: the independent speeds, e.g. ``["phi'", "delta'", "thr'"]`` (as
            ``nhc derive --speeds``); default: the scene's ``dependent`` key, else the first
            coordinates whose constraint columns are independent at the initial point.
        :raises ImportError: SymPy is not installed.
        :raises nhc.SceneError: a speed list that names no coordinate's derivative, or the wrong
            number of speeds, or dependent speeds that cannot be solved for."""
        from .sympy_form import SympyEquations, _sympy
        _sympy()
        if self._scene is None:
            return SympyEquations(self.json, self.model)
        document = _json.loads(self._scene.reduced_json(self.model, list(speeds or [])))
        return SympyEquations(document, self.model, list(self._scene.inputs))

    def _repr_latex_(self) -> str:
        """Math only (align* blocks, headings as \\text rows): MathJax renders math, not \\section."""
        return str(self.latex_math).strip()

    def __repr__(self) -> str:
        return self.text


class Analysis:
    """`nhc analyze` of one model: `index`, `dof`, `needed` (the initial values it takes),
    `initial_point` (name -> value at t0: those values, then the leading derivatives) and
    `condition` (of the system Jacobian there)."""

    def __init__(self, result: Dict[str, Any]) -> None:
        self.model = result["model"]
        self.index = result["index"]
        self.dof = result["dof"]
        self.needed = list(result["needed"])
        self.initial_point = dict(result["initial_point"])
        self.condition = result["condition"]

    def __repr__(self) -> str:
        return (f"Analysis(model={self.model!r}, index={self.index}, dof={self.dof}, "
                f"needed={self.needed!r})")


class Scene:
    """A scene (TOML) read and checked: `Scene.load(path, set={...})` or `Scene.from_toml(text)`.
    Bad input raises nhc.SceneError with the file, line and column."""

    def __init__(self, scene: _nhc._Scene, written: Optional[_nhc._Scene] = None) -> None:
        self._scene = scene
        # The scene as written (before set=): the models are compiled from it, and the set= values
        # are passed at run time, so a parameter study compiles once (docs/python.md).
        self._written = written

    @classmethod
    def load(cls, path: str | _os.PathLike[str], set: Optional[Mapping[str, float]] = None,
             expand: bool = False) -> Scene:
        """Reads and checks the scene file `path` (as every nhc command does).

        :param path: the scene's TOML file.
        :param set: parameter values replacing the scene's (as ``--set P=V``): ``{"r": 0.4}``.
        :param expand: substitute the ``[definitions]`` into the equations (as ``--expand``)
            instead of keeping them as named intermediates.
        :returns: the scene.
        :raises nhc.SceneError: bad input, with ``.file``, ``.line`` and ``.column``."""
        written = _nhc._Scene.load(str(path), {}, expand)
        return cls(written.with_parameters(dict(set)), written) if set else cls(written)

    @classmethod
    def from_toml(cls, text: str, path: str | _os.PathLike[str] = "scene.toml",
                  set: Optional[Mapping[str, float]] = None, expand: bool = False) -> Scene:
        """Reads and checks a scene given as TOML text.

        :param text: the scene, as a scene file would hold it.
        :param path: the name its messages give the text (and where relative paths in it start).
        :param set: parameter values replacing the scene's (as ``--set P=V``).
        :param expand: substitute the ``[definitions]`` (as ``--expand``).
        :raises nhc.SceneError: bad input, at its line and column in `text`."""
        written = _nhc._Scene.from_toml(text, str(path), {}, expand)
        return cls(written.with_parameters(dict(set)), written) if set else cls(written)

    @property
    def name(self) -> str:
        """The scene's ``name``."""
        return self._scene.name

    @property
    def coordinates(self) -> List[str]:
        """The scene's ``coordinates``, in order."""
        return list(self._scene.coordinates)

    @property
    def parameters(self) -> Dict[str, float]:
        """The ``[parameters]`` (with `set` applied): name -> value."""
        return dict(self._scene.parameters)

    @property
    def inputs(self) -> List[str]:
        """The scene's ``[inputs]`` names."""
        return list(self._scene.inputs)

    @property
    def default_model(self) -> str:
        """The model the commands take when none is named: the scene's ``[simulate]`` model, else
        chetaev when the scene lists it, else its first model."""
        return self._scene.default_model

    @property
    def models(self) -> List[str]:
        """The models the scene asks for (``models``; all four by default)."""
        return list(self._scene.models)

    def derive(self, model: Optional[str] = None) -> Derivation:
        """The equations of one model, as ``nhc derive`` writes them.

        :param model: ``"vakonomic"``, ``"chetaev"``, ``"holder"`` or ``"suslov"`` (default: the
            scene's ``[simulate]`` model, else chetaev, as on the command line).
        :raises nhc.SceneError: an unknown model name."""
        return Derivation(self._scene.derive(model or self._scene.default_model), self._scene)

    def analyze(self, model: Optional[str] = None) -> Analysis:
        """The structural analysis of one model (as ``nhc analyze``): index, degrees of freedom, the
        initial values it needs and the consistent initial point.

        :param model: the model's name (default: the scene's ``[simulate]`` model, as on the command line).
        :raises nhc.MathError: the given initial values miss a hidden constraint."""
        return Analysis(self._scene.analyze(model or self._scene.default_model))

    def build(self, model: Optional[str] = None, backend: str = "compiled") -> Model:
        """The model derived, compiled (both caches) and loaded: an :class:`nhc.Model` to simulate.

        The code is generated from the scene as written and the ``set=`` values are passed at run
        time (as ``nhc simulate --set`` does), so scenes loaded with other ``set=`` values reuse the
        compiled model: a parameter study compiles once.

        :param model: the model's name (default: the scene's ``[simulate]`` model, as on the command line).
        :param backend: ``"compiled"``, ``"interpreted"`` (no compiler; a scene interpreted before,
            in this process or another, takes its program from the scene cache without deriving)
            or ``"auto"`` (compiled when compiled before, else interpreted), as ``nhc simulate
            --backend``; docs/interpreter.md.
        :raises nhc.MathError: the given initial values miss a hidden constraint (checked before
            anything is compiled, in ``nhc simulate``'s words).
        :raises nhc.HostError: the compiler or the cache failed."""
        return Model(_nhc._build(self._scene, model or self._scene.default_model, self._written, backend))

    def linearize(self, model: Optional[str] = None, at: Optional[Mapping[str, float]] = None,
                  keep: Sequence[str] = (), states: Sequence[str] = (), turn: str = "") -> Linearization:
        """Linear stability at the scene's [initial] with `at` values replaced (as ``nhc linearize --at``).

        :param model: the model's name (default: the scene's ``[simulate]`` model, as on the command line).
        :param at: parameters and initial values to replace: ``{"phi'": 0, "v": 3}``.
        :param keep: cyclic coordinates to keep as states (as ``--keep``): ``["x"]``.
        :param states: the reduced states wanted, in this order (as ``--states``): ``["x", "x'", "th", "th'"]``.
        :param turn: ``"ANGLE:X,Y"`` (as ``--turn``): linearize about a steady turn, a relative
            equilibrium of the rotations of the X, Y plane that move ANGLE, in the turning frame.
        :returns: A, B, C, D, the eigenvalues and the verdict."""
        return Linearization(_nhc._linearize(self._scene, model or self._scene.default_model, {k: float(v) for k, v in (at or {}).items()},
                                             list(keep), list(states), str(turn)))

    def sweep(self, model: str, name: str, values: _npt.ArrayLike,
              at: Optional[Mapping[str, float]] = None, keep: Sequence[str] = (),
              states: Sequence[str] = ()) -> Sweep:
        """Linearizes at each of `values` of the parameter or initial value `name`, and refines where
        the verdict changes (as ``nhc linearize --sweep``).

        :param model: the model's name.
        :param name: a parameter (``"v"``) or an initial value (``"psi'"``).
        :param values: at least two, increasing and equally spaced (as ``np.linspace`` gives).
        :param at: other values to replace, as for :meth:`linearize`.
        :param keep: cyclic coordinates kept as states, as for :meth:`linearize`.
        :param states: the reduced states, as for :meth:`linearize`.
        :raises nhc.SceneError: values not increasing or not equally spaced."""
        values = _np.asarray(values, dtype=float).ravel()
        if len(values) < 2 or not _np.all(_np.diff(values) > 0):
            raise SceneError("sweep values must be at least two, increasing")
        if _np.max(_np.abs(_np.diff(values) - (values[-1] - values[0]) / (len(values) - 1))) > 1e-9 * _np.max(_np.abs(values)):
            raise SceneError("sweep values must be equally spaced (np.linspace)")
        at = {k: float(v) for k, v in (at or {}).items()}
        return Sweep(name, _nhc._sweep(self._scene, model, name, values[0], values[-1], len(values), at,
                                       list(keep), list(states)))

    def optimize(self, intervals: Optional[int] = None, guess: Optional[str | _os.PathLike[str] | Run] = None,
                 max_iterations: int = 3000, tolerance: float = 1e-10, jacobian: str = "exact",
                 hessian: str = "exact", path_tolerance: float = 1e-6) -> Run:
        """An optimal motion of the scene's [optimize] problem (as ``nhc optimize``): Hermite–Simpson
        collocation solved by IPOPT (docs/optimize.md). Without [inputs] the coordinates' paths are
        the unknowns (the vakonomic problem); with them, the model's equations hold and the inputs
        are the controls.

        :param intervals: collocation intervals (default: [optimize] intervals, else 40).
        :param guess: the starting path: a CSV file (``nhc simulate``'s or ``nhc optimize``'s) or a
            :class:`Run` (a previous optimum); default the straight line between the boundary values.
        :param max_iterations: IPOPT's iteration limit.
        :param tolerance: IPOPT's tolerance on the scaled optimality error.
        :param jacobian: ``"exact"`` or ``"finite-differences"`` (IPOPT's own, on the same sparsity).
        :param hessian: ``"exact"`` or ``"limited-memory"`` (IPOPT's quasi-Newton).
        :param path_tolerance: the largest path error accepted, relative to the states' scale
            (docs/optimize.md, "Path error"); above it the mesh is refined, and if that cannot meet
            it, MathError. ``summary["path_error"]`` is the measured one. The optimum is local.
        :returns: the path on the collocation points (t, the states and their rates, the inputs),
            with :attr:`Run.cost` and ``summary`` (cost, violation, iterations, t_end, status).
        :raises nhc.MathError: no optimum: infeasible (the message names the condition violated
            most), the iteration limit (``.run`` holds the last point) or another IPOPT failure.
        :raises nhc.SceneError: no [optimize] table, or a bad entry or argument."""
        columns: Optional[List[str]] = None
        rows: Optional[List[List[float]]] = None
        name = ""
        if isinstance(guess, Run):
            columns, rows, name = list(guess.columns), guess.to_numpy().tolist(), "the guess"
        elif guess is not None:
            name = _os.fspath(guess)  # read by nhc's one CSV reader, under the data-file rules
        result = _nhc._optimize(self._scene, None if intervals is None else int(intervals), int(max_iterations),
                                float(tolerance), str(jacobian), str(hessian), float(path_tolerance), columns, rows, name,
                                name if columns is None and guess is not None else "")
        summary = result["summary"]
        run = Run({"columns": result["columns"], "data": result["data"], "summary": summary, "cost": summary["cost"]})
        if summary["status"] != "optimal":
            worst = (f"; the largest violation, {summary['violation']:.3g}, is in {summary['worst_constraint']}"
                     if summary["violation"] > 0 else "")
            lead = "no path meets the conditions: " if summary["status"] == "infeasible" else ""
            if summary["status"] == "path_error":
                error = MathError(f"optimize: {summary['words']}")
                error.run = run
                raise error
            error = MathError(f"optimize: {lead}{summary['words']} ({summary['iterations']} iterations){worst}")
            error.run = run  # the last point IPOPT reached
            raise error
        return run

    def __repr__(self) -> str:
        return f"Scene({self.name!r}, coordinates={self.coordinates!r})"
