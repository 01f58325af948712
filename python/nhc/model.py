"""nhc.Model and nhc.Run: a scene's model compiled and run; runs as numpy arrays (docs/python.md)."""
import numpy as _np

from . import _nhc
from .errors import MathError, SceneError


def _count(name, value):
    """A whole number for a count argument: 2.5 or "ten" is a SceneError naming it, as --outputs 2.5 is."""
    try:
        whole = int(value)
    except (TypeError, ValueError):
        raise SceneError(f"{name}: {value!r} is not a whole number", file=name) from None
    if whole != value:
        raise SceneError(f"{name}: {value!r} is not a whole number", file=name)
    return max(-2**62, min(whole, 2**62))  # beyond any limit either way; the rule's message follows


class Run:
    """One integration: the columns of `nhc simulate`'s CSV as arrays.

    run.t, run["x"], run["x'"], run.columns, run.to_numpy() (rows: output times), run.summary
    (steps, evaluations, the time split, drift), run.plot(), run.to_pandas()."""

    def __init__(self, result):
        self.columns = list(result["columns"])
        self._data = _np.asarray(result["data"])
        self._index = {name: k for k, name in enumerate(self.columns)}
        self._summary = result["summary"]  # built on first use
        self._max_discrete_constraint = result.get("max_discrete_constraint")  # the variational integrator's

    @property
    def summary(self):
        """steps, evaluations, the time split and the drift (hidden constraints, reference,
        invariants): a dict, measured on first use."""
        if callable(self._summary):
            self._summary = self._summary()
            if self._max_discrete_constraint is not None:
                self._summary["max_discrete_constraint"] = self._max_discrete_constraint
        return self._summary

    @property
    def t(self):
        return self._data[:, 0]

    def __getitem__(self, name):
        if name not in self._index:
            raise KeyError(f"no column {name!r} (columns: {', '.join(self.columns)})")
        return self._data[:, self._index[name]]

    def __contains__(self, name):
        return name in self._index

    def __len__(self):
        return self._data.shape[0]

    def to_numpy(self):
        return self._data.copy()

    def to_pandas(self):
        import pandas  # only when asked for
        return pandas.DataFrame(self._data, columns=self.columns)

    def plot(self, x=None, y=None, ax=None):
        """The coordinates against t, or y against x (run.plot(x="x", y="y")): a matplotlib figure."""
        import matplotlib.pyplot as plt  # only when asked for
        if ax is None:
            figure, ax = plt.subplots()
        else:
            figure = ax.figure
        if x is not None or y is not None:
            ax.plot(self[x or "t"], self[y], label=f"{y}({x or 't'})")
            ax.set_xlabel(x or "t")
            ax.set_ylabel(y)
            ax.set_aspect("equal", adjustable="datalim")
        else:
            for name in self._coordinates():
                ax.plot(self.t, self[name], label=name)
            ax.set_xlabel("t")
            ax.legend()
        return figure

    def _coordinates(self):
        # The order-0 columns of the coordinates: names without primes, before the multipliers.
        return [c for c in self.columns[1:]
                if "'" not in c and ":" not in c and not c.startswith(("lambda", "d("))]

    def __repr__(self):
        return f"Run({len(self)} rows, columns={self.columns!r})"


class Model:
    """A scene's model, derived, compiled (both caches) and loaded: scene.build("chetaev")."""

    def __init__(self, built):
        self._model = built

    state_names = property(lambda self: list(self._model.state_names))
    inputs = property(lambda self: list(self._model.inputs))
    parameters = property(lambda self: dict(self._model.parameters))
    name = property(lambda self: self._model.model_name)

    def simulate(self, t_end=None, rtol=None, atol=None, outputs=None, output_times=None, inputs=None,
                 max_steps=1000000, sensitivity=None, integrator="ida", step=None):
        """Integrates from the scene's [initial]; a Run. A failure raises nhc.MathError with .t.
        t_end, rtol, atol and outputs not given are the scene's [simulate] values (else 1, 1e-8,
        1e-10 and 200), as on the command line, whose rules every argument obeys (nhc.SceneError).
        `inputs`: u(t, y) -> the model's inputs (self.inputs order), called at every residual
        evaluation with y in state_names order; without it, the scene's default signals.
        `sensitivity`: names of parameters and given initial values (["alpha", "x'(0)"]): the run
        also carries the forward sensitivities (IDAS) as columns "d(x)/d(alpha)", "d(x')/d(x'(0))".
        `integrator="variational", step=H`: the discrete Lagrange-d'Alembert integrator at the fixed
        step H (chetaev model; docs/variational.md), for long runs whose energy must not drift; its
        summary also has "newton_iterations" and "max_discrete_constraint".
        Ctrl-C (KeyboardInterrupt) stops a long run."""
        times = None if output_times is None else [float(t) for t in _np.asarray(output_times).ravel()]
        names = None if sensitivity is None else [sensitivity] if isinstance(sensitivity, str) else list(sensitivity)
        def number(value):
            return None if value is None else float(value)

        result = self._model.simulate(number(t_end), number(rtol), number(atol),
                                      None if outputs is None else _count("outputs", outputs), times, inputs,
                                      _count("max_steps", max_steps), names, str(integrator), number(step))
        if "failure" in result:
            error = MathError(result["failure"], t=result["failure_t"])
            error.run = Run(result)  # the motion up to the failure
            raise error
        return Run(result)

    def residual(self, t, y, yp):
        """F(t, y, y') of the index-1 system (state_names order), as numpy."""
        return self._model.residual(float(t), _np.asarray(y, dtype=float), _np.asarray(yp, dtype=float))

    def jacobian(self, t, y, yp, cj):
        """dF/dy + cj dF/dy' as an n x n numpy array."""
        return self._model.jacobian(float(t), _np.asarray(y, dtype=float), _np.asarray(yp, dtype=float), float(cj))

    def __repr__(self):
        return f"Model({self.name!r}, states={self.state_names!r})"


class Linearization:
    """`nhc linearize` at one point: A, B, C, D (numpy), states, inputs, outputs, eigenvalues
    (complex numpy), verdict, families, point."""

    def __init__(self, result):
        self.states = list(result["states"])
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

    def __repr__(self):
        return f"Linearization(states={self.states!r}, verdict={self.verdict!r})"


class Sweep:
    """`nhc linearize --sweep` over equally spaced values: `values`, `points` (a Linearization
    each), `verdicts`, `eigenvalues` (one complex array per value) and `thresholds` (the refined
    values where the verdict changes: dicts with value, from, to)."""

    def __init__(self, name, result):
        self.name = name
        self.points = [Linearization(p) for p in result["points"]]
        self.values = _np.array([p["value"] for p in result["points"]])
        self.verdicts = [p.verdict for p in self.points]
        self.eigenvalues = [p.eigenvalues for p in self.points]
        self.thresholds = [dict(t) for t in result["thresholds"]]

    def __repr__(self):
        return f"Sweep({self.name!r}, {len(self.values)} values, thresholds={[t['value'] for t in self.thresholds]})"
