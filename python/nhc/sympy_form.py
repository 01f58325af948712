"""Derived equations as SymPy objects (``Derivation.to_sympy()``, docs/python.md).

The expressions come from nhc's JSON form (``nhc derive --format json``). They are parsed with
``sympy.parse_expr`` only after every name in them has been checked against the names the JSON
itself declares (coordinates and their derivatives, multipliers, parameters, definitions, t) and
a fixed list of functions, with a global namespace that holds SymPy's number constructors and
nothing else: file data is never evaluated as Python.
"""
from __future__ import annotations

import re as _re
from typing import Any, Dict, List, Mapping, Optional, Sequence

_FUNCTIONS = ("sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh",
              "asinh", "acosh", "atanh", "exp", "log", "sqrt", "abs", "Pi", "Euler")
_NAME = _re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_ALLOWED = _re.compile(r"^[A-Za-z0-9_+\-*/^().,\s]*$")


def _sympy() -> Any:
    try:
        import sympy
    except ImportError as error:  # pragma: no cover - depends on the environment
        raise ImportError(
            "Derivation.to_sympy() needs SymPy, which is not installed: pip install sympy "
            "(Debian: apt install python3-sympy)") from error
    return sympy


def primed(name: str, order: int) -> str:
    """x, x', x'': the scene's spelling of a derivative."""
    return name + "'" * order


class SympyEquations:
    """One model's equations as SymPy objects, in the scene's names.

    ``residuals``: equation name (``"R_x"``) -> expression (= 0); ``constraints``: list;
    ``definitions``: the named intermediates, name -> expression, each after those it uses;
    ``symbols``: every name -> its SymPy symbol (coordinates as named in the scene, derivatives
    ``x'``, ``x''``, multipliers, parameters, definitions). Where the multiplier-free form exists:
    ``speeds`` (``["phi'", …]``), ``dependent_speeds`` (``"x'"`` -> expression of q and the
    speeds), ``mass_matrix`` (M_r, a SymPy Matrix), ``forcing`` (f_r, a column Matrix) and
    ``multipliers`` (name -> expression of q, the speeds and their derivatives); otherwise
    ``speeds`` is None and ``reduced_reason`` says why. The reduced expressions hold every q'
    and q'': evaluate them with the dependent speeds substituted; they do not depend on q''
    except through the speeds' own derivatives (docs/reduced-form.md). ``expand(e)``
    substitutes the definitions and the dependent speeds and sets the second derivatives of the
    dependent coordinates to zero."""

    def __init__(self, document: Mapping[str, Any], model: str, inputs: Sequence[str] = ()) -> None:
        sp = _sympy()
        self.symbols: Dict[str, Any] = {}
        local: Dict[str, Any] = {}
        for printed, info in document["symbols"].items():
            symbol = sp.Symbol(primed(info["of"], int(info["order"])), real=True)
            local[printed] = symbol
            self.symbols[str(symbol)] = symbol
        for p in list(document["parameters"]) + list(inputs):
            local[p] = self.symbols.setdefault(p, sp.Symbol(p, real=True))
        local["t"] = self.symbols.setdefault("t", sp.Symbol("t", real=True))
        for d in document["definitions"]:
            local[d["name"]] = self.symbols.setdefault(d["name"], sp.Symbol(d["name"], real=True))
        for f in _FUNCTIONS:
            local[f] = {"Pi": sp.pi, "Euler": sp.EulerGamma, "abs": sp.Abs}.get(f) or getattr(sp, f)
        self._local = local
        self._sp = sp

        self.definitions: Dict[str, Any] = {d["name"]: self._parse(d["expression"])
                                            for d in document["definitions"]}
        entry = document["models"][model]
        self.model = model
        self.residuals: Dict[str, Any] = {name: self._parse(e)
                                          for name, e in zip(entry["equation_names"], entry["equations"])}
        self.constraints: List[Any] = [self._parse(e) for e in entry["constraints"]]
        self.speeds: Optional[List[str]] = None
        self.reduced_reason: Optional[str] = None
        self.dependent_speeds: Dict[str, Any] = {}
        self.mass_matrix: Any = None
        self.forcing: Any = None
        self.multipliers: Dict[str, Any] = {}
        reduced = entry.get("reduced")
        if reduced is None:
            return
        if not reduced["available"]:
            self.reduced_reason = reduced["reason"]
            return
        self.speeds = list(reduced["speeds"])
        self.dependent_speeds = {n: self._parse(e)
                                 for n, e in zip(reduced["dependent"], reduced["dependent_speeds"])}
        self.mass_matrix = sp.Matrix([[self._parse(e) for e in row] for row in reduced["mass_matrix"]])
        self.forcing = sp.Matrix([self._parse(e) for e in reduced["forcing"]])
        self.multipliers = {n: self._parse(e)
                            for n, e in zip(reduced["multiplier_names"], reduced["multipliers"])}

    def _parse(self, text: str) -> Any:
        if not _ALLOWED.match(text):
            raise ValueError(f"unexpected characters in an expression from nhc: {text!r}")
        for name in _NAME.findall(text):
            if name not in self._local:
                raise ValueError(f"unknown name {name!r} in an expression from nhc: {text!r}")
        from sympy.parsing.sympy_parser import (auto_number, convert_xor, factorial_notation,
                                                parse_expr)
        constructors = {"Integer": self._sp.Integer, "Float": self._sp.Float,
                        "Rational": self._sp.Rational, "__builtins__": {}}
        return parse_expr(text, local_dict=dict(self._local), global_dict=constructors,
                          transformations=(auto_number, factorial_notation, convert_xor))

    def symbol(self, name: str) -> Any:
        """The SymPy symbol of a name as the scene writes it.

        :param name: ``"x"``, ``"x'"``, ``"m"``, a definition's name."""
        return self.symbols[name]

    def _expand_definitions(self, e: Any) -> Any:
        for name in reversed(list(self.definitions)):
            e = e.subs(self.symbols[name], self.definitions[name])
        return e

    def expand(self, e: Any) -> Any:
        """e with the definitions substituted (last to first), then the dependent speeds, and the
        dependent coordinates' second derivatives set to zero (the reduced form does not depend
        on them).

        :param e: a SymPy expression or matrix of these equations."""
        e = self._expand_definitions(e)
        if self.dependent_speeds:
            e = e.subs({self.symbols[n]: self._expand_definitions(v)
                        for n, v in self.dependent_speeds.items()})
            e = e.subs({self.symbols[n + "'"]: 0 for n in self.dependent_speeds if n + "'" in self.symbols})
        return e
