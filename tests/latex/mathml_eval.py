"""Reading nhc's LaTeX back through an independent parser: pandoc (texmath) turns the TeX math into
MathML, and this module evaluates that MathML at given values of the variables, so that a printed
equation can be compared with the text form it was printed from.

What it reads is what nhc prints: numbers, names (single letters, Greek letters, upright
multi-letter names, subscripts), derivatives as accents (\\dot, \\ddot, \\dddot) or x^{(k)},
partial derivatives \\frac{\\partial T}{\\partial x} and \\frac{d}{dt}X as names of intermediates,
fractions, powers, square roots, |x|, function application, implicit products, and the plain
parentheses of rows that were broken between pieces (a ")^{2}" closing a power).

A name is resolved against the names the text form uses: the LaTeX of a name is read into the
candidate text names it may stand for (q_{1} is q1 or q_1, \\dot{T} is T_d1 or T_dot), and the one
the text row contains is taken; a name with no candidate there is an error (a printer that drops
or invents a name fails, as one that drops a bracket does).
"""
import re
import subprocess
import xml.etree.ElementTree as ET

import mpmath

M = "{http://www.w3.org/1998/Math/MathML}"

GREEK = {
    "α": "alpha", "β": "beta", "γ": "gamma", "δ": "delta", "ϵ": "epsilon", "ε": "epsilon", "ζ": "zeta",
    "η": "eta", "θ": "theta", "ϑ": "theta", "ι": "iota", "κ": "kappa", "λ": "lambda", "μ": "mu", "ν": "nu",
    "ξ": "xi", "π": "pi", "ρ": "rho", "σ": "sigma", "τ": "tau", "υ": "upsilon", "ϕ": "phi", "φ": "phi",
    "χ": "chi", "ψ": "psi", "ω": "omega", "Γ": "Gamma", "Δ": "Delta", "Θ": "Theta", "Λ": "Lambda",
    "Ξ": "Xi", "Π": "Pi", "Σ": "Sigma", "Υ": "Upsilon", "Φ": "Phi", "Ψ": "Psi", "Ω": "Omega",
}
ACCENTS = {"\u0307": 1, "\u0308": 2, "\u20db": 3, "˙": 1, "¨": 2}
FUNCTIONS = {
    "sin": mpmath.sin, "cos": mpmath.cos, "tan": mpmath.tan, "exp": mpmath.exp, "ln": mpmath.log,
    "log": mpmath.log, "sinh": mpmath.sinh, "cosh": mpmath.cosh, "tanh": mpmath.tanh,
    "arcsin": mpmath.asin, "asin": mpmath.asin, "arccos": mpmath.acos, "acos": mpmath.acos,
    "arctan": mpmath.atan, "atan": mpmath.atan, "atan2": lambda y, x: mpmath.atan2(y, x),
    "arsinh": mpmath.asinh, "asinh": mpmath.asinh, "arcosh": mpmath.acosh, "acosh": mpmath.acosh,
    "artanh": mpmath.atanh, "atanh": mpmath.atanh, "abs": abs, "sqrt": mpmath.sqrt,
}
MINUS = {"-", "\u2212"}
CONSTANTS = {"pi": mpmath.pi, "i": mpmath.mpc(0, 1)}  # \pi, and \mathrm{i} of a complex number
TIMES = {"\u22c5", "\u00b7", "\u00d7", "*", "\u2062"}


class ReadError(Exception):
    pass


def to_mathml(formulas):
    """MathML trees of TeX formulas (one pandoc run for all)."""
    if not formulas:
        return []
    source = "\n\n".join("$" + f + "$" for f in formulas) + "\n"
    html = subprocess.run(["pandoc", "-f", "latex", "-t", "html", "--mathml"], input=source,
                          capture_output=True, text=True, check=True).stdout
    maths = re.findall(r"<math\b.*?</math>", html, flags=re.S)
    if len(maths) != len(formulas):
        raise ReadError(f"pandoc returned {len(maths)} formulas for {len(formulas)}")
    trees = []
    for m in maths:
        root = ET.fromstring(m)
        semantics = root.find(M + "semantics")
        body = semantics[0] if semantics is not None else root
        trees.append(body)
    return trees


def tag(e):
    return e.tag.replace(M, "")


def text_of(e):
    return "".join(e.itertext()).strip()


# ----- names ---------------------------------------------------------------------------------

def plain_name(e):
    """The name an identifier element spells (None when e is no name)."""
    t = tag(e)
    if t == "mi":
        s = text_of(e)
        if s in GREEK:
            return GREEK[s]
        if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", s):
            return s
        return None
    if t == "mstyle" and len(e) > 0 and all(tag(c) in ("mi", "mn") for c in e):
        s = "".join(GREEK.get(text_of(c), text_of(c)) for c in e)
        return s if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", s) else None
    return None


def name_candidates(e):
    """Text names the element may stand for, or None when it is not a name."""
    t = tag(e)
    base = plain_name(e)
    if base is not None:
        return [base]
    if t == "mrow" and len(e) >= 2 and all(is_time_derivative(c) for c in e[:-1]):  # \frac{d}{dt}X
        inner = name_candidates(e[-1])
        return None if inner is None else [n + "_dot" * (len(e) - 1) for n in inner]
    if t == "mover" and len(e) == 2 and tag(e[1]) == "mo" and text_of(e[1]) in ACCENTS:
        inner = name_candidates(e[0])
        if inner is None:
            return None
        k = ACCENTS[text_of(e[1])]
        out = [n + "_d" + str(k) for n in inner]
        if k == 1:
            out += [n + "_dot" for n in inner]
        return out
    if t == "msub" and len(e) == 2:
        # A_{1,y} is A_1_y: the indices of a definition's entries, joined by underscores.
        sub = "".join(GREEK.get(c, c) for c in text_of(e[1])).replace(" ", "").replace(",", "_")
        if not re.fullmatch(r"[A-Za-z0-9_]+", sub):
            return None
        if tag(e[0]) == "mover" and len(e[0]) == 2 and text_of(e[0][1]) in ACCENTS:
            inner = name_candidates(e[0][0])
            if inner is None:
                return None
            k = ACCENTS[text_of(e[0][1])]
            return [n + j + sub + "_d" + str(k) for n in inner for j in ("", "_")]
        inner = name_candidates(e[0])
        if inner is None:
            return None
        return [n + j + sub for n in inner for j in ("", "_")]
    if t == "msup" and len(e) == 2:
        m = re.fullmatch(r"\((\d+)\)", text_of(e[1]).replace(" ", ""))
        inner = name_candidates(e[0])
        if m and inner is not None:
            return [n + "_d" + m.group(1) for n in inner]
        return None
    if t == "mfrac" and len(e) == 2:
        num, den = list(e[0]) if tag(e[0]) == "mrow" else [e[0]], list(e[1]) if tag(e[1]) == "mrow" else [e[1]]
        if len(num) >= 2 and text_of(num[0]) == "\u2202" and len(den) == 2 and text_of(den[0]) == "\u2202":
            of = name_candidates(wrap(num[1:]))
            by = name_candidates(den[1])
            if of is None or by is None:
                return None
            return ["d" + a + "_d" + b for a in of for b in by]
    return None


def wrap(elements):
    if len(elements) == 1:
        return elements[0]
    row = ET.Element(M + "mrow")
    row.extend(elements)
    return row


def is_time_derivative(e):
    """\\frac{d}{dt}: an operator on the name after it."""
    return (tag(e) == "mfrac" and len(e) == 2 and text_of(e[0]) == "d" and
            text_of(e[1]).replace(" ", "") == "dt")


# ----- evaluation ----------------------------------------------------------------------------

def resolve(values, candidates, shown):
    for c in candidates:
        if c in values:
            return values[c]
    for c in candidates:
        if c in CONSTANTS:
            return CONSTANTS[c]
    raise ReadError(f"no variable of the text form for {shown} (read as {candidates})")


def variable(candidates, shown):
    return lambda values: resolve(values, candidates, shown)


class Compiler:
    """Reads a MathML tree once into a function of `values` (text name -> number)."""

    def tokens(self, elements):
        """The flat token list of a row: ('num', v), ('op', s), ('func', name), ('pow', element),
        ('ddt',), ('abs', elements), ('atom', element)."""
        out = []
        for e in elements:
            t = tag(e)
            if t in ("mspace", "annotation"):
                continue
            if t == "mrow":
                if len(e) >= 2 and tag(e[0]) == "mo" and text_of(e[0]) == "|":
                    out.append(("abs", list(e)[1:-1]))
                else:
                    out.extend(self.tokens(list(e)))
                continue
            if t == "mo":
                s = text_of(e)
                if s in MINUS:
                    out.append(("op", "-"))
                elif s in TIMES:
                    out.append(("op", "*"))
                elif s in ("+", "/", "(", ")", ","):
                    out.append(("op", s))
                elif s in FUNCTIONS:
                    out.append(("func", s))
                elif s == "":
                    continue
                else:
                    raise ReadError(f"unknown operator {s!r}")
                continue
            if t == "mi" and text_of(e) == "/":
                out.append(("op", "/"))
                continue
            if t == "mi" and text_of(e) in FUNCTIONS and plain_name(e) is None:
                out.append(("func", text_of(e)))
                continue
            if t == "mn":
                out.append(("num", mpmath.mpf(text_of(e))))
                continue
            if t == "msup" and tag(e[0]) == "mo" and text_of(e[0]) == ")":
                out.append(("op", ")"))  # a broken row's ")^{k}": the power of the bracket
                out.append(("pow", e[1]))
                continue
            if is_time_derivative(e):
                out.append(("ddt",))
                continue
            out.append(("atom", e))
        return out

    def row(self, elements):
        toks = self.tokens(elements)
        pos, f = self.expr(toks, 0)
        if pos != len(toks):
            raise ReadError(f"unread tokens after position {pos}: {toks[pos:pos + 5]}")
        return f

    def element(self, e):
        return self.row([e])

    def atom(self, e):
        names = name_candidates(e)
        if names is not None:
            return variable(names, ET.tostring(e, encoding="unicode")[:200])
        t = tag(e)
        if t == "mfrac":
            num, den = self.element(e[0]), self.element(e[1])
            return lambda v: num(v) / den(v)
        if t == "msqrt":
            arg = self.row(list(e))
            return lambda v: mpmath.sqrt(arg(v))
        if t == "msup":
            base, exponent = self.element(e[0]), self.element(e[1])
            return lambda v: mpmath.power(base(v), exponent(v))
        if t == "mstyle":
            return self.row(list(e))
        raise ReadError(f"cannot read {ET.tostring(e, encoding='unicode')[:200]}")

    def expr(self, toks, pos):
        negative = False
        if pos < len(toks) and toks[pos] in (("op", "-"), ("op", "+")):
            negative = toks[pos][1] == "-"
            pos += 1
        pos, first = self.term(toks, pos)
        terms = [(negative, first)]
        while pos < len(toks) and toks[pos] in (("op", "+"), ("op", "-")):
            op = toks[pos][1]
            pos, f = self.term(toks, pos + 1)
            terms.append((op == "-", f))

        def total(v):
            out = 0
            for minus, f in terms:
                out = out - f(v) if minus else out + f(v)
            return out
        return pos, total

    def starts_primary(self, tok):
        return tok[0] in ("num", "func", "atom", "abs", "ddt") or tok == ("op", "(")

    def term(self, toks, pos):
        if pos < len(toks) and toks[pos] == ("op", "-"):  # "-" inside a product: a negative factor
            pos, f = self.term(toks, pos + 1)
            return pos, lambda v: -f(v)
        pos, first = self.power(toks, pos)
        factors = [(False, first)]
        while pos < len(toks):
            tok = toks[pos]
            if tok in (("op", "*"), ("op", "/")):
                pos, f = self.power(toks, pos + 1)
                factors.append((tok[1] == "/", f))
            elif self.starts_primary(tok):
                pos, f = self.power(toks, pos)
                factors.append((False, f))
            else:
                break

        def product(v):
            out = 1
            for divide, f in factors:
                out = out / f(v) if divide else out * f(v)
            return out
        return pos, product

    def power(self, toks, pos):
        pos, f = self.primary(toks, pos)
        while pos < len(toks) and toks[pos][0] == "pow":
            base, exponent = f, self.element(toks[pos][1])
            f = (lambda b, x: lambda v: mpmath.power(b(v), x(v)))(base, exponent)
            pos += 1
        return pos, f

    def primary(self, toks, pos):
        if pos >= len(toks):
            raise ReadError("expression ends where a factor is expected")
        tok = toks[pos]
        if tok[0] == "num":
            value = tok[1]
            return pos + 1, lambda v: value
        if tok[0] == "atom":
            return pos + 1, self.atom(tok[1])
        if tok[0] == "abs":
            arg = self.row(tok[1])
            return pos + 1, lambda v: abs(arg(v))
        if tok[0] == "ddt":
            times = 0
            while pos < len(toks) and toks[pos] == ("ddt",):
                times, pos = times + 1, pos + 1
            nxt = toks[pos] if pos < len(toks) else None
            names = name_candidates(nxt[1]) if nxt and nxt[0] == "atom" else None
            if names is None:
                raise ReadError("d/dt before something that is not a name")
            return pos + 1, variable([n + "_dot" * times for n in names], "d/dt " + str(names))
        if tok == ("op", "("):
            pos, f = self.expr(toks, pos + 1)
            if pos >= len(toks) or toks[pos] != ("op", ")"):
                raise ReadError("unbalanced parenthesis")
            return pos + 1, f
        if tok[0] == "func":
            if pos + 1 >= len(toks) or toks[pos + 1] != ("op", "("):
                raise ReadError(f"function {tok[1]} without an argument list")
            args = []
            pos += 2
            while True:
                pos, f = self.expr(toks, pos)
                args.append(f)
                if pos < len(toks) and toks[pos] == ("op", ","):
                    pos += 1
                    continue
                break
            if pos >= len(toks) or toks[pos] != (("op", ")")):
                raise ReadError(f"unbalanced argument list of {tok[1]}")
            function = FUNCTIONS[tok[1]]
            return pos + 1, lambda v: function(*[a(v) for a in args])
        raise ReadError(f"unexpected token {tok}")


def compile_tree(tree):
    """The MathML tree as a function of a dict of values (text name -> number)."""
    return Compiler().element(tree)


def evaluate(tree, values):
    return compile_tree(tree)(values)


# ----- the text form -------------------------------------------------------------------------

IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


TEXT_CONSTANTS = ("Pi", "I", "Euler", "Catalan")  # GiNaC's constants and imaginary unit


def text_names(text):
    return {n for n in IDENT.findall(text) if n not in FUNCTIONS and n not in TEXT_CONSTANTS}


def text_function(text):
    """The text form as a function of its names, read by SymPy (an independent parser)."""
    import sympy
    from sympy.parsing.sympy_parser import parse_expr
    names = sorted(text_names(text))
    symbols = {n: sympy.Symbol(n) for n in names}
    local = dict(symbols)
    local.update({"sqrt": sympy.sqrt, "sin": sympy.sin, "cos": sympy.cos, "tan": sympy.tan,
                  "exp": sympy.exp, "log": sympy.log, "abs": sympy.Abs, "atan2": sympy.atan2,
                  "asin": sympy.asin, "acos": sympy.acos, "atan": sympy.atan, "sinh": sympy.sinh,
                  "cosh": sympy.cosh, "tanh": sympy.tanh, "asinh": sympy.asinh, "acosh": sympy.acosh,
                  "atanh": sympy.atanh, "Pi": sympy.pi, "I": sympy.I, "Euler": sympy.EulerGamma,
                  "Catalan": sympy.Catalan})
    expr = parse_expr(text.replace("^", "**"), local_dict=local, evaluate=False)
    return names, sympy_function(expr)


def sympy_function(expr):
    """A SymPy expression as a function of a dict of values, evaluated with mpmath node by node
    (SymPy's own evalf or lambdify print or simplify first, slowly for long expressions)."""
    import sympy
    if expr.is_Symbol:
        name = expr.name
        return lambda v: v[name]
    if expr.is_Rational:
        value = mpmath.mpf(expr.p) / expr.q
        return lambda v: value
    if expr.is_Number:
        value = mpmath.mpf(str(expr))
        return lambda v: value
    if expr is sympy.pi:
        return lambda v: mpmath.pi
    if expr is sympy.I:
        return lambda v: mpmath.mpc(0, 1)
    args = [sympy_function(a) for a in expr.args]
    if expr.is_Add:
        return lambda v: mpmath.fsum(a(v) for a in args)
    if expr.is_Mul:
        def product(v):
            out = 1
            for a in args:
                out = out * a(v)
            return out
        return product
    if expr.is_Pow:
        base, exponent = args
        return lambda v: mpmath.power(base(v), exponent(v))
    functions = {sympy.sin: mpmath.sin, sympy.cos: mpmath.cos, sympy.tan: mpmath.tan, sympy.exp: mpmath.exp,
                 sympy.log: mpmath.log, sympy.Abs: abs, sympy.atan2: mpmath.atan2, sympy.asin: mpmath.asin,
                 sympy.acos: mpmath.acos, sympy.atan: mpmath.atan, sympy.sinh: mpmath.sinh,
                 sympy.cosh: mpmath.cosh, sympy.tanh: mpmath.tanh, sympy.asinh: mpmath.asinh,
                 sympy.acosh: mpmath.acosh, sympy.atanh: mpmath.atanh, sympy.re: mpmath.re, sympy.im: mpmath.im}
    if expr.func in functions:
        f = functions[expr.func]
        return lambda v: f(*[a(v) for a in args])
    raise ValueError(f"no numeric reading of {expr.func}")


def close(a, b, digits=25):
    scale = max(1, abs(a), abs(b))
    return abs(a - b) <= mpmath.mpf(10) ** (-digits) * scale
