"""nhc.Model and nhc.Run: a scene's model compiled and run; runs as numpy arrays (docs/python.md)."""
from __future__ import annotations

from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union
from typing import cast as _cast

import numpy as _np
import numpy.typing as _npt

from . import _nhc
from .errors import MathError, SceneError

from ._nhc import Mpc as Mpc  # model predictive control's settings (docs/mpc.md), as `mpc = { … }` of [controller]


def _count(name: str, value: Any) -> int:
    """A whole number for a count argument: 2.5 or "ten" is a SceneError naming it, as --outputs 2.5 is."""
    try:
        whole = int(value)
    except (TypeError, ValueError):
        raise SceneError(f"{name}: {value!r} is not a whole number", file=name) from None
    if whole != value:
        raise SceneError(f"{name}: {value!r} is not a whole number", file=name)
    return max(-2**62, min(whole, 2**62))  # beyond any limit either way; the rule's message follows


class Event:
    """An event the run met (the scene's ``[events]``, ``stop_when``): its `name`, the time `t` of
    the zero crossing (located by IDA to the integration tolerance) and the `state` there (state
    name -> value)."""

    def __init__(self, name: str, t: float, state: Dict[str, float]) -> None:
        self.name = name
        self.t = t
        self.state = state

    def __repr__(self) -> str:
        return f"Event({self.name!r}, t={self.t!r})"


class Run:
    """One integration: the columns of `nhc simulate`'s CSV as arrays.

    run.t, run["x"], run["x'"], run.columns, run.to_numpy() (rows: output times), run.summary
    (steps, evaluations, the time split, drift), run.events, run.plot(), run.to_pandas(). From
    :meth:`nhc.Scene.optimize`: the optimal path on the collocation points and its :attr:`cost`."""

    columns: List[str]
    """The column names, in the CSV's order: ``t`` first."""

    events: List[Event]
    """The events met, in time order (the scene's ``[events]``, ``stop_when``)."""
    cost: Optional[float]
    """The objective's value of an optimal motion (:meth:`nhc.Scene.optimize`); None for a simulation."""

    def __init__(self, result: Dict[str, Any]) -> None:
        self.columns = list(result["columns"])
        self._data = _np.asarray(result["data"])
        self._index = {name: k for k, name in enumerate(self.columns)}
        self._summary = result["summary"]  # built on first use
        self._mpc = result.get("mpc")  # model predictive control's line, as nhc simulate prints it
        self._max_discrete_constraint = result.get("max_discrete_constraint")  # the variational integrator's
        self.events = [Event(str(e["name"]), float(e["t"]), dict(e["state"])) for e in result.get("events", [])]
        self.cost = result.get("cost")

    @property
    def summary(self) -> Dict[str, Any]:
        """steps, evaluations, the time split and the drift (hidden constraints, reference,
        invariants): a dict, measured on first use."""
        if callable(self._summary):
            self._summary = self._summary()
            if self._max_discrete_constraint is not None:
                self._summary["max_discrete_constraint"] = self._max_discrete_constraint
            if self._mpc is not None:
                self._summary["model_predictive_control"] = self._mpc
        return _cast(Dict[str, Any], self._summary)

    @property
    def t(self) -> _npt.NDArray[_np.float64]:
        """The output times (the column ``t``)."""
        return self._data[:, 0]

    def __getitem__(self, name: str) -> _npt.NDArray[_np.float64]:
        """The column `name` (``"x"``, ``"x'"``, ``"lambda1"``, ``"invariant:energy"``) as an array.

        :param name: a column name, as in :attr:`columns`.
        :raises KeyError: no such column (the message lists them)."""
        if name not in self._index:
            raise KeyError(f"no column {name!r} (columns: {', '.join(self.columns)})")
        return self._data[:, self._index[name]]

    def __contains__(self, name: object) -> bool:
        """Whether the run has the column `name`."""
        return name in self._index

    def __len__(self) -> int:
        """The number of rows (output times)."""
        return int(self._data.shape[0])

    def to_numpy(self) -> _npt.NDArray[_np.float64]:
        """All columns as one array (a copy): rows are output times, columns as :attr:`columns`."""
        return self._data.copy()

    def to_pandas(self) -> Any:
        """The run as a pandas DataFrame (Debian ``python3-pandas``; imported only when asked for)."""
        import pandas  # only when asked for
        return pandas.DataFrame(self._data, columns=self.columns)

    def plot(self, x: Optional[str] = None, y: Optional[str] = None, ax: Any = None) -> Any:
        """The coordinates against t, or y against x (``run.plot(x="x", y="y")``): a matplotlib figure.

        :param x: the column on the horizontal axis (default ``t``); with `y`, equal scales.
        :param y: the column to draw; without `x` and `y`, every coordinate against t.
        :param ax: the matplotlib axes to draw into (default: a new figure).
        :returns: the matplotlib figure drawn into."""
        import matplotlib.pyplot as plt  # only when asked for
        if ax is None:
            figure, ax = plt.subplots()
        else:
            figure = ax.figure
        if x is not None or y is not None:
            ax.plot(self[x or "t"], self[_cast(str, y)], label=f"{y}({x or 't'})")
            ax.set_xlabel(x or "t")
            ax.set_ylabel(y)
            ax.set_aspect("equal", adjustable="datalim")
        else:
            for name in self._coordinates():
                ax.plot(self.t, self[name], label=name)
            ax.set_xlabel("t")
            ax.legend()
        return figure

    def _coordinates(self) -> List[str]:
        # The order-0 columns of the coordinates: names without primes, before the multipliers.
        return [c for c in self.columns[1:]
                if "'" not in c and ":" not in c and not c.startswith(("lambda", "d("))]

    def __repr__(self) -> str:
        return f"Run({len(self)} rows, columns={self.columns!r})"


class Model:
    """A scene's model, derived, compiled (both caches) and loaded: ``scene.build("chetaev")``."""

    def __init__(self, built: _nhc._Model) -> None:
        self._model = built

    @property
    def state_names(self) -> List[str]:
        """The states of the index-1 system, in the order of `y` in :meth:`residual`."""
        return list(self._model.state_names)

    @property
    def inputs(self) -> List[str]:
        """The scene's ``[inputs]``, in the order an `inputs` function returns them."""
        return list(self._model.inputs)

    @property
    def parameters(self) -> Dict[str, float]:
        """The parameters its runs take (name -> value): the scene's, with the ``set=`` values (the
        compiled code is shared by every ``set=``; these are passed at run time)."""
        return dict(self._model.parameters)

    @property
    def name(self) -> str:
        """The model's name: ``"vakonomic"``, ``"chetaev"``, ``"holder"`` or ``"suslov"``."""
        return self._model.model_name

    def simulate(self, t_end: Optional[float] = None, rtol: Optional[float] = None, atol: Optional[float] = None,
                 outputs: Optional[int] = None,
                 output_times: Optional[Iterable[float]] = None,
                 inputs: Optional[Callable[[float, _npt.NDArray[_np.float64]], Sequence[float]]] = None,
                 max_steps: int = 1000000, sensitivity: Union[str, Sequence[str], None] = None,
                 integrator: str = "ida", step: Optional[float] = None, stop_when: Optional[str] = None,
                 initial: Optional[Mapping[str, float]] = None, t0: Optional[float] = None,
                 controller: Union[Callable[[float, _npt.NDArray[_np.float64], Any], Tuple[Sequence[float], Any]], bool, Mpc, None] = None,
                 period: Optional[float] = None, controller_state: Any = None,
                 max_step: Optional[float] = None, initial_step: Optional[float] = None) -> Run:
        """Integrates from the scene's [initial] (as ``nhc simulate``) and returns the :class:`Run`.

        Arguments not given take the scene's ``[simulate]`` values (else 1, 1e-8, 1e-10 and 200), as on
        the command line, whose rules every argument obeys (:class:`nhc.SceneError`).

        :param t_end: the end of the run (from the scene's t0).
        :param rtol: IDA's relative tolerance.
        :param atol: IDA's absolute tolerance.
        :param outputs: the number of output intervals (outputs + 1 rows).
        :param output_times: the output times instead (increasing; the last is the end of the run).
        :param inputs: u(t, y) -> the model's inputs (:attr:`inputs` order), called at every residual
            evaluation with y in :attr:`state_names` order; without it, the scene's default signals.
        :param max_steps: the limit on IDA's internal steps over the run.
        :param sensitivity: names of parameters and given initial values (``["alpha", "x'(0)"]``): the
            run also carries the forward sensitivities (IDAS) as columns ``"d(x)/d(alpha)"``,
            ``"d(x')/d(x'(0))"``.
        :param integrator: ``"ida"``, or ``"variational"`` with `step`: the discrete
            Lagrange-d'Alembert integrator at a fixed step (chetaev model; docs/variational.md), for
            long runs whose energy must not drift; its summary also has ``newton_iterations`` and
            ``max_discrete_constraint``.
        :param step: the variational integrator's fixed step.
        :param stop_when: an expression (of t, the coordinates, their derivatives, the multipliers)
            whose first zero crossing ends the run (the event ``stop_when``; as ``--stop-when``).
            The scene's ``[events]`` are located in every IDA run: :attr:`Run.events`.
        :param initial: ``[initial]`` values from outside the scene, as if written there (as
            ``--initial``): ``{"th": 0.2, "th'": 0.0}``, coordinates and multipliers with as many
            primes as the derivative's order; the consistent initial point is found as for the
            scene's own values.
        :param t0: the start of the run instead of the scene's t0.
        :param controller: a sampled controller f(t, y, state) -> (inputs, new_state), called only
            at the sample times t0 + k*period, k = 0 ... N (the last sample too; y in
            :attr:`state_names` order, the state the run reached there); its inputs are held
            (zero-order hold) until the next sample, and the integrator restarts exactly at each
            sample (the states stay; y' and the algebraic states follow the new inputs). The rows
            are the samples; the run ends at the last one at or before `t_end` (without it, the scene's
            ``[simulate]`` t_end, t0 + 1 without one, as a plain run). Without a function, a
            scene with ``[controller]`` runs that (its states are the columns
            ``"controller:NAME"``); ``controller=False`` runs such a scene without it. The scene's
            ``[events]``, `stop_when` and its contacts (stop and slide) are located between the
            samples; not with `outputs`, `output_times`, `sensitivity` or the variational
            integrator, nor `inputs` with a function controller (it sets every input). The one
            engine of ``nhc simulate``'s (docs/combinations.md).
        :param max_step: IDA's largest step (as ``--max-step``; default none).
        :param initial_step: IDA's first step (as ``--initial-step``; default from the problem's
            scale: the first output time, the tolerances, the
            rates).
            ``controller=nhc.Mpc(horizon=1.5, intervals=15)`` runs model predictive control of the
            scene's ``[optimize]`` problem (docs/mpc.md) at the scene's ``[controller]`` period or
            `period`; a scene whose ``[controller]`` has ``mpc`` runs that by default (columns
            ``"mpc:cost"``, ``"mpc:iterations"``, ``"mpc:seconds"``; the summary's
            ``"model_predictive_control"`` line).
        :param period: the controller's sample period h (with a controller function or nhc.Mpc).
        :param controller_state: the controller's state at t0 (passed to its first call; each call
            returns the next).
        :returns: the run's columns as arrays.
        :raises nhc.MathError: the run failed (``.t`` is where; ``.run`` the motion up to there).
        :raises nhc.SceneError: a bad argument (an unknown sensitivity name, bad output times).

        Ctrl-C (KeyboardInterrupt) stops a long run."""
        if controller is None and self._model.has_controller:
            controller = True  # the scene's [controller]
        if controller is False:
            controller = None  # the scene without its [controller]
        times = None if output_times is None else [float(t) for t in _np.asarray(output_times).ravel()]
        names = None if sensitivity is None else [sensitivity] if isinstance(sensitivity, str) else list(sensitivity)
        def number(value: Optional[float]) -> Optional[float]:
            return None if value is None else float(value)

        result = self._model.simulate(number(t_end), number(rtol), number(atol),
                                      None if outputs is None else _count("outputs", outputs), times, inputs,
                                      _count("max_steps", max_steps), names, str(integrator), number(step),
                                      None if stop_when is None else str(stop_when),
                                      None if initial is None else [(str(k), float(v)) for k, v in initial.items()],
                                      number(t0), controller, number(period), controller_state,
                                      number(max_step), number(initial_step))
        if "failure" in result:
            error = MathError(result["failure"], t=result["failure_t"])
            error.run = Run(result)  # the motion up to the failure
            raise error
        return Run(result)

    def residual(self, t: float, y: _npt.ArrayLike, yp: _npt.ArrayLike,
                 u: Optional[_npt.ArrayLike] = None) -> _npt.NDArray[_np.float64]:
        """F(t, y, y', u) of the index-1 system, as numpy (for one's own solvers).

        :param t: the time.
        :param y: the states, in :attr:`state_names` order.
        :param yp: their derivatives, in the same order.
        :param u: the inputs (:attr:`inputs` order); without it, the scene's default signals at t."""
        values = None if u is None else [float(v) for v in _np.asarray(u, dtype=float).ravel()]
        return self._model.residual(float(t), _np.asarray(y, dtype=float), _np.asarray(yp, dtype=float), values)

    def jacobian(self, t: float, y: _npt.ArrayLike, yp: _npt.ArrayLike, cj: float) -> _npt.NDArray[_np.float64]:
        """dF/dy + cj dF/dy' as an n x n numpy array (IDA's iteration matrix).

        :param t: the time.
        :param y: the states, in :attr:`state_names` order.
        :param yp: their derivatives.
        :param cj: the scalar multiplying dF/dy' (IDA's cj)."""
        return self._model.jacobian(float(t), _np.asarray(y, dtype=float), _np.asarray(yp, dtype=float), float(cj))

    @property
    def coordinates(self) -> List[str]:
        """The coordinates' names, in the order of q in :meth:`mass_matrix`, :meth:`forcing` and
        :meth:`velocities`."""
        return list(self._model.coordinates)

    @property
    def speeds(self) -> List[str]:
        """The independent speeds u of the multiplier-free form M_r u' = f_r (``["phi'", ...]``,
        docs/reduced-form.md); empty when the model has no such form."""
        return list(self._model.speeds)

    @property
    def speed_coordinates(self) -> List[int]:
        """For each independent speed, the index in :attr:`coordinates` of the coordinate whose
        first derivative it is."""
        return list(self._model.speed_coordinates)

    def _reduced(self, which: int, t: float, q: _npt.ArrayLike, u: _npt.ArrayLike,
                 inputs: Optional[_npt.ArrayLike]) -> _npt.NDArray[_np.float64]:
        values = None if inputs is None else [float(v) for v in _np.asarray(inputs, dtype=float).ravel()]
        return self._model.reduced_function(which, float(t), _np.asarray(q, dtype=float),
                                            _np.asarray(u, dtype=float), values)

    def mass_matrix(self, t: float, q: _npt.ArrayLike, u: _npt.ArrayLike,
                    inputs: Optional[_npt.ArrayLike] = None) -> _npt.NDArray[_np.float64]:
        """M_r(t, q, u) of the multiplier-free form M_r u' = f_r, a k x k numpy array (k =
        ``len(speeds)``); with :meth:`forcing` and :meth:`velocities` the model is an ODE in
        (q, u) for one's own integrator (docs/reduced-form.md).

        :param t: the time.
        :param q: the coordinates, in :attr:`coordinates` order.
        :param u: the independent speeds, in :attr:`speeds` order.
        :param inputs: the inputs (:attr:`inputs` order); without it, the scene's default signals at t.
        :raises nhc.MathError: when the model has no multiplier-free form."""
        return self._reduced(1, t, q, u, inputs)

    def forcing(self, t: float, q: _npt.ArrayLike, u: _npt.ArrayLike,
                inputs: Optional[_npt.ArrayLike] = None) -> _npt.NDArray[_np.float64]:
        """f_r(t, q, u) of the multiplier-free form M_r u' = f_r, k numbers.

        :param t: the time.
        :param q: the coordinates, in :attr:`coordinates` order.
        :param u: the independent speeds, in :attr:`speeds` order.
        :param inputs: the inputs (:attr:`inputs` order); without it, the scene's default signals at t.
        :raises nhc.MathError: when the model has no multiplier-free form."""
        return self._reduced(2, t, q, u, inputs)

    def velocities(self, t: float, q: _npt.ArrayLike, u: _npt.ArrayLike,
                   inputs: Optional[_npt.ArrayLike] = None) -> _npt.NDArray[_np.float64]:
        """q'(t, q, u): the independent speeds u in their places and the dependent speeds from
        the constraints, one per coordinate (the kinematic half of the ODE).

        :param t: the time.
        :param q: the coordinates, in :attr:`coordinates` order.
        :param u: the independent speeds, in :attr:`speeds` order.
        :param inputs: the inputs (:attr:`inputs` order); without it, the scene's default signals at t.
        :raises nhc.MathError: when the model has no multiplier-free form."""
        return self._reduced(0, t, q, u, inputs)

    def input_jacobian(self, t: float, y: _npt.ArrayLike, yp: _npt.ArrayLike,
                       u: Optional[_npt.ArrayLike] = None) -> _npt.NDArray[_np.float64]:
        """dF/du of the index-1 residual F(t, y, y', u): an n x m numpy array (rows: residuals,
        columns: :attr:`inputs`), from exact derivatives evaluated in doubles.

        :param t: the time.
        :param y: the states, in :attr:`state_names` order.
        :param yp: their derivatives.
        :param u: the inputs (:attr:`inputs` order); without it, the scene's default signals at t."""
        values = None if u is None else [float(v) for v in _np.asarray(u, dtype=float).ravel()]
        return self._model.input_jacobian(float(t), _np.asarray(y, dtype=float), _np.asarray(yp, dtype=float), values)

    def linearize_along(self, run: Run,
                        inputs: Optional[Callable[[float, _npt.NDArray[_np.float64]], Sequence[float]]] = None,
                        keep: Sequence[str] = (), states: Sequence[str] = ()) -> LinearizationAlong:
        """The linearization along a run, for time-varying LQR: d(δs)/dt = A(t) δs + B(t) δu at each
        of the run's samples, on the reduced states of :meth:`nhc.Scene.linearize` (cyclic
        coordinates removed unless kept, the states the hidden constraints fix eliminated;
        docs/linearize.md, "Along a motion").

        :param run: a run of this model (its state columns and their derivatives are read).
        :param inputs: u(t, y) as the run had them (as for :meth:`simulate`); without it, the
            scene's default signals.
        :param keep: cyclic coordinates to keep as states (``["x"]``).
        :param states: the reduced states, in this order (so that they do not change along the run).
        :returns: t, A (N x n x n), B (N x n x m), states, inputs.
        :raises nhc.MathError: a singular system at a sample, or other states eliminated than at the first."""
        names = self.state_names
        differential = self._model.differential
        rows = len(run)
        y = _np.column_stack([run[name] for name in names]) if names else _np.zeros((rows, 0))
        columns = []
        for name, moving in zip(names, differential):
            if not moving:
                columns.append(_np.zeros(rows))  # an algebraic state's derivative is not in the equations
            elif name + "'" in run:
                columns.append(run[name + "'"])
            else:
                raise SceneError(f"the run has no column {name + chr(39)!r} (the derivative of the state {name!r})")
        yp = _np.column_stack(columns) if columns else _np.zeros((rows, 0))
        result = self._model.linearize_along([float(t) for t in run.t], y, yp, inputs, list(keep), list(states))
        return LinearizationAlong(run.t.copy(), result)

    def __repr__(self) -> str:
        return f"Model({self.name!r}, states={self.state_names!r})"


class LinearizationAlong:
    """:meth:`Model.linearize_along`: ``t`` (the run's sample times), ``A`` (N x n x n), ``B``
    (N x n x m), ``states`` (the reduced states, rows and columns of each A) and ``inputs``."""

    def __init__(self, t: _npt.NDArray[_np.float64], result: Dict[str, Any]) -> None:
        self.t = t
        self.A = _np.asarray(result["A"])
        self.B = _np.asarray(result["B"])
        self.states = list(result["states"])
        self.inputs = list(result["inputs"])

    def __len__(self) -> int:
        """The number of samples."""
        return len(self.t)

    def __repr__(self) -> str:
        return f"LinearizationAlong({len(self.t)} samples, states={self.states!r})"


class Linearization:
    """`nhc linearize` at one point: A, B, C, D (numpy), states, inputs, outputs, eigenvalues
    (complex numpy), verdict, families, point, cyclic (the coordinates removed), kept (the
    cyclic coordinates kept as states) and turn_rate (about a steady turn: the frame's rate)."""

    def __init__(self, result: Dict[str, Any]) -> None:
        self.states = list(result["states"])
        self.cyclic = list(result["cyclic"])
        self.kept = list(result["kept"])
        self.turn_rate = float(result["turn_rate"])
        self.inputs = list(result["inputs"])
        self.outputs = list(result["outputs"])
        self.A, self.B = _np.asarray(result["A"]), _np.asarray(result["B"])
        self.C, self.D = _np.asarray(result["C"]), _np.asarray(result["D"])
        self.eigenvalues = _np.asarray(result["eigenvalues"], dtype=complex)
        self.verdict = result["verdict"]
        self.zero_eigenvalues = result["zero_eigenvalues"]
        self.families = list(result["families"])
        self.point = dict(result["point"])
        self.notes = list(result["notes"])

    def __repr__(self) -> str:
        return f"Linearization(states={self.states!r}, verdict={self.verdict!r})"


class Sweep:
    """`nhc linearize --sweep` over equally spaced values: `values`, `points` (a Linearization
    each), `verdicts`, `eigenvalues` (one complex array per value) and `thresholds` (the refined
    values where the verdict changes: dicts with value, from, to)."""

    def __init__(self, name: str, result: Dict[str, Any]) -> None:
        self.name = name
        self.points = [Linearization(p) for p in result["points"]]
        self.values = _np.array([p["value"] for p in result["points"]])
        self.verdicts = [p.verdict for p in self.points]
        self.eigenvalues = [p.eigenvalues for p in self.points]
        self.thresholds = [dict(t) for t in result["thresholds"]]

    def __repr__(self) -> str:
        return f"Sweep({self.name!r}, {len(self.values)} values, thresholds={[t['value'] for t in self.thresholds]})"
