#!/usr/bin/env python3
"""The peers of the benchmark on the knife-edge chain (bench/knife_chain.py), one N per call.

SymPy: sympy.physics.mechanics.LagrangesMethod with the N constraints as nonhol_coneqs derives
Lagrange's equations with multipliers, which for first-order constraints are Chetaev's:
    M(q, u) [q'; u'; lambda] = F(q, u)        (mass_matrix_full, forcing_full)
  - derive_s: LagrangesMethod + form_lagranges_equations + mass_matrix_full + forcing_full;
  - cse_s and the operation count of sympy.cse's output (count_ops of every replacement and
    every reduced expression, the nonzero entries of M and F);
  - lambdify_s: lambdify(M, F) with cse=True (NumPy code; the code generation step).
SciPy: solve_ivp (Radau, BDF) on q' = u, u' from M z = F (numpy.linalg.solve at every
evaluation), at the tolerances of the scene family, from the same consistent initial state.

The paper's second example (Appell-Hamel) is available too: peers.py appell_hamel.

Usage: peers.py N|appell_hamel [--no-integrate] [--no-residual-ops] [--methods Radau,BDF]
prints one JSON object
"""
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import knife_chain  # noqa: E402

import numpy as np  # noqa: E402
import sympy  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols  # noqa: E402


def chain_system(n):
    """The knife-edge chain of bench/knife_chain.py."""
    t = dynamicsymbols._t
    params = sympy.symbols([name for name, _ in knife_chain.PARAMETERS], real=True)
    m, J, g, alpha, k, l = params
    xs = dynamicsymbols("x1:%d" % (n + 1))
    ys = dynamicsymbols("y1:%d" % (n + 1))
    ths = dynamicsymbols("th1:%d" % (n + 1))
    q, names = [], []
    for i in range(n):
        q += [xs[i], ys[i], ths[i]]
        names += ["x%d" % (i + 1), "y%d" % (i + 1), "th%d" % (i + 1)]
    L = 0
    for i in range(n):
        xd, yd, thd = xs[i].diff(t), ys[i].diff(t), ths[i].diff(t)
        L += m / 2 * (xd ** 2 + yd ** 2) + J / 2 * thd ** 2 + m * g * sympy.sin(alpha) * xs[i]
    for i in range(n - 1):
        L -= k / 2 * ((xs[i + 1] - xs[i]) ** 2 + (ys[i + 1] - ys[i] - l) ** 2)
    cons = [xs[i].diff(t) * sympy.sin(ths[i]) - ys[i].diff(t) * sympy.cos(ths[i]) for i in range(n)]
    q0, u0 = [], []
    for (x, xd, y, th, thd) in knife_chain.initial_values(n):
        q0 += [x, y, th]
        u0 += [xd, xd * math.tan(th), thd]
    return dict(L=L, q=q, names=names, cons=cons, params=params,
                values=[v for _, v in knife_chain.PARAMETERS], q0=q0, u0=u0,
                t_end=knife_chain.T_END, rtol=knife_chain.RTOL, atol=knife_chain.ATOL)


def appell_hamel_system():
    """examples/appell_hamel.toml (the paper's second example): a particle with
    z' = (b/a) sqrt(x'^2 + y'^2); its [initial] and [simulate] values."""
    t = dynamicsymbols._t
    params = sympy.symbols(["m", "g", "a", "b"], real=True)
    m, g, a, b = params
    x, y, z = dynamicsymbols("x y z")
    L = m / 2 * (x.diff(t) ** 2 + y.diff(t) ** 2 + z.diff(t) ** 2) - m * g * z
    cons = [z.diff(t) - b / a * sympy.sqrt(x.diff(t) ** 2 + y.diff(t) ** 2)]
    values = [1.0, 9.81, 1.0, 0.5]
    u0 = [1.0, 0.5, 0.5 * math.sqrt(1.25)]
    return dict(L=L, q=[x, y, z], names=["x", "y", "z"], cons=cons, params=params, values=values,
                q0=[0.0, 0.0, 0.0], u0=u0, t_end=0.2, rtol=1e-8, atol=1e-10)


def derive(system):
    start = time.perf_counter()
    lm = LagrangesMethod(system["L"], system["q"], nonhol_coneqs=system["cons"])
    lm.form_lagranges_equations()
    M = lm.mass_matrix_full
    F = lm.forcing_full
    derive_s = time.perf_counter() - start
    return lm, M, F, derive_s


def count_ops_after_cse(exprs):
    start = time.perf_counter()
    replacements, reduced = sympy.cse(exprs)
    cse_s = time.perf_counter() - start
    ops = sum(sympy.count_ops(rhs) for _, rhs in replacements) + sum(sympy.count_ops(e) for e in reduced)
    before = sum(sympy.count_ops(e) for e in exprs)
    return cse_s, int(before), int(ops), len(replacements)


def plain_symbols(q):
    """Plain symbols for q and u = q' (lambdify's arguments)."""
    t = dynamicsymbols._t
    qs = sympy.symbols(["q%d" % i for i in range(len(q))], real=True)
    us = sympy.symbols(["u%d" % i for i in range(len(q))], real=True)
    subs = {qi.diff(t): ui for qi, ui in zip(q, us)}
    subs.update({qi: si for qi, si in zip(q, qs)})
    return qs, us, subs


def main(argv):
    if argv[1] == "appell_hamel":
        system = appell_hamel_system()
        n = argv[1]
    else:
        n = int(argv[1])
        system = chain_system(n)
    integrate = "--no-integrate" not in argv
    methods = ["Radau", "BDF"]
    if "--methods" in argv:
        methods = argv[argv.index("--methods") + 1].split(",")
    out = {"N": n, "sympy_version": sympy.__version__}
    import scipy
    out["scipy_version"] = scipy.__version__

    q, params = system["q"], system["params"]
    lm, M, F, derive_s = derive(system)
    out["derive_s"] = derive_s
    out["mass_matrix_size"] = M.shape[0]
    exprs = [e for e in list(M) + list(F) if e != 0]
    cse_s, before, after, n_repl = count_ops_after_cse(exprs)
    out["cse_s"] = cse_s
    out["ops_before_cse"] = before
    out["ops_after_cse"] = after
    out["cse_replacements"] = n_repl

    # The same functions nhc generates: the residual of the index-1 form in IDA's terms,
    # r(y, y') = M(y) y' - F(y) with y = (q, u, lambda) and y' = (q', u', -), and its iteration
    # matrix dr/dy + cj dr/dy' (nonzero entries).
    if "--no-residual-ops" not in argv:
        start = time.perf_counter()
        nq = len(q)
        ys = sympy.symbols(["y%d" % i for i in range(2 * nq + M.shape[0] - 2 * nq)], real=True)
        yps = sympy.symbols(["yp%d" % i for i in range(2 * nq)], real=True)
        cj = sympy.Symbol("cj", real=True)
        t = dynamicsymbols._t
        to_y = {qi.diff(t): ys[nq + i] for i, qi in enumerate(q)}
        to_y.update({qi: ys[i] for i, qi in enumerate(q)})
        to_y.update({lam: ys[2 * nq + a] for a, lam in enumerate(lm.lam_vec)})
        unknowns = sympy.Matrix(list(yps) + list(ys[2 * nq:]))
        r = M.xreplace(to_y) * unknowns - F.xreplace(to_y)
        jac = r.jacobian(ys) + cj * r.jacobian(yps).row_join(sympy.zeros(r.shape[0], len(ys) - len(yps)))
        out["residual_form_s"] = time.perf_counter() - start
        _, rb, ra, _ = count_ops_after_cse([e for e in r if e != 0])
        out["residual_ops_before_cse"], out["residual_ops_after_cse"] = rb, ra
        cse_rj_s, rjb, rja, _ = count_ops_after_cse([e for e in list(r) + list(jac) if e != 0])
        out["residual_jacobian_ops_before_cse"], out["residual_jacobian_ops_after_cse"] = rjb, rja
        out["residual_jacobian_cse_s"] = cse_rj_s

    qs, us, subs = plain_symbols(q)
    start = time.perf_counter()
    Mp = M.xreplace(subs)
    Fp = F.xreplace(subs)
    args = list(qs) + list(us) + list(params)
    mass = sympy.lambdify(args, Mp, modules="numpy", cse=True)
    force = sympy.lambdify(args, Fp, modules="numpy", cse=True)
    out["lambdify_s"] = time.perf_counter() - start
    out["derive_generate_s"] = derive_s + out["lambdify_s"]

    if integrate:
        nq = len(q)
        p = list(system["values"])
        s0 = np.array(list(system["q0"]) + list(system["u0"]))

        def rhs(_t, s):
            a = list(s) + p
            z = np.linalg.solve(np.asarray(mass(*a), dtype=float), np.asarray(force(*a), dtype=float).ravel())
            return z[: 2 * nq]

        names = system["names"]
        for method in methods:
            start = time.perf_counter()
            sol = solve_ivp(rhs, (0.0, system["t_end"]), s0, method=method,
                            rtol=system["rtol"], atol=system["atol"])
            seconds = time.perf_counter() - start
            final = {}
            for i, name in enumerate(names):
                final[name] = float(sol.y[i, -1])
                final[name + "'"] = float(sol.y[nq + i, -1])
            out[method] = {
                "integrate_s": seconds,
                "success": bool(sol.success),
                "message": sol.message,
                "steps": int(len(sol.t) - 1),
                "nfev": int(sol.nfev),
                "njev": int(sol.njev),
                "nlu": int(sol.nlu),
                "t_final": float(sol.t[-1]),
                "final": final,
            }
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
