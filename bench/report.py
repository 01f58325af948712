#!/usr/bin/env python3
"""Turns the measurements of bench/run.sh (JSON, one file per run) into bench/results.md and the
plot data; every number in results.md comes from those files.

Usage: report.py JSON_DIR RESULTS_MD PLOT_DATA
  JSON_DIR holds nhc_<scene>.json (nhc_bench), peers_<N|appell_hamel>.json (peers.py),
  env.json (machine, versions, N sets, wall time) and optionally plot.txt (gnuplot's text plot).
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def fmt_s(v):
    if v is None:
        return "–"
    if v >= 100:
        return "%.0f s" % v
    if v >= 1:
        return "%.2f s" % v
    if v >= 1e-3:
        return "%.3g ms" % (v * 1e3)
    if v >= 1e-6:
        return "%.3g µs" % (v * 1e6)
    return "%.3g ns" % (v * 1e9)


def fmt_x(v):
    if v is None:
        return "–"
    if v >= 100:
        return "%.0f×" % v
    if v >= 10:
        return "%.1f×" % v
    return "%.2f×" % v


def ratio(a, b):
    if a is None or b is None or b == 0:
        return None
    return a / b


def fit_slope(points):
    """Least-squares slope of log y against log x."""
    pts = [(math.log(x), math.log(y)) for x, y in points if x > 0 and y and y > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    sxy = sum((p[0] - mx) * (p[1] - my) for p in pts)
    return sxy / sxx if sxx else None


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    for r in rows:
        out.append("| " + " | ".join(str(c) for c in r) + " |")
    return "\n".join(out)


def code_bytes(library):
    """Bytes of machine code of residual + the Jacobian functions in a shared object (nm -S)."""
    import subprocess
    try:
        text = subprocess.run(["nm", "-S", "-C", library], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    total = 0
    for line in text.splitlines():
        parts = line.split(None, 3)
        if len(parts) == 4 and parts[2] in ("W", "T", "t", "w") and \
                any("::%s(" % f in parts[3] for f in ("residual", "jacobian", "jacobian_values")):
            total += int(parts[1], 16)
    return total or None


def unique_symbols(library):
    """Number of STB_GNU_UNIQUE symbols in a shared object (readelf -Ws), None if unreadable."""
    import subprocess
    try:
        text = subprocess.run(["readelf", "-Ws", library], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    return sum(1 for line in text.splitlines() if " UNIQUE " in line)


def distinct_objects(d, gen_lib, hw_lib):
    """Which two loaded objects one hand-written row compares: libraries, table addresses, and
    whether either could alias the other through GNU_UNIQUE symbols."""
    g, h = d.get("generated_table_address"), d.get("handwritten_table_address")
    if not g or not h:
        return "not recorded"
    uniq = [unique_symbols(x) if os.path.isfile(x) else None for x in (gen_lib, hw_lib)]
    uniq_text = "GNU_UNIQUE symbols %s / %s" % tuple("?" if u is None else u for u in uniq)
    return "`%s`: %s vs `%s`: %s (%s; %s)" % (
        d.get("generated_library", "?"), g, d.get("handwritten_library", "?"), h,
        "distinct" if g != h else "**the same table**", uniq_text)


def final_difference(nhc, method_result):
    """Max |nhc − SciPy| over the coordinates and velocities at t_end."""
    if not nhc or not method_result or not method_result.get("success"):
        return None
    values = dict(zip(nhc["final_state_names"], nhc["final_y"]))
    diffs = [abs(values[k] - v) for k, v in method_result["final"].items() if k in values]
    return max(diffs) if diffs else None


def main(argv):
    jdir, results_path, plot_data = argv[1], argv[2], argv[3]
    env = load(os.path.join(jdir, "env.json")) or {}
    ns = env.get("nhc_N", [])
    peer_ns = env.get("peer_N", [])
    nhc = {n: load(os.path.join(jdir, "nhc_knife_chain_%d.json" % n)) for n in ns}
    peers = {n: load(os.path.join(jdir, "peers_%d.json" % n)) for n in peer_ns}
    examples = {name: load(os.path.join(jdir, "nhc_%s.json" % name)) for name in ("appell_hamel", "particle")}
    peer_ah = load(os.path.join(jdir, "peers_appell_hamel.json"))

    # The size from which nhc generates a sparse Jacobian, as the driver reports it
    # (nhc::kSparseJacobianFromStates), not a copy of the policy.
    thresholds = {d.get("sparse_jacobian_from_states") for d in list(nhc.values()) + list(examples.values()) if d}
    threshold = "/".join(str(t) for t in sorted(thresholds, key=str)) if thresholds else "?"

    L = []
    L.append("# Benchmarks: nhc against SymPy/SciPy and hand-written code")
    L.append("")
    L.append("Generated by `bench/run.sh` (do not edit; rerun it). %s." % env.get("date", ""))
    L.append("Machine: %s, %s cores; load average %s at the start, %s at the end (other work on the "
             "machine inflates wall times; all timings are wall-clock, best of several runs where "
             "runs are short). Compiler: %s. SymPy %s, SciPy %s, NumPy %s. Whole run: %s."
             % (env.get("cpu", "?"), env.get("cores", "?"), env.get("load_start", "?"), env.get("load_end", "?"),
                env.get("compiler", "?"), env.get("sympy", "?"), env.get("scipy", "?"), env.get("numpy", "?"),
                fmt_s(env.get("wall_s"))))
    L.append("")
    L.append("Scenes: the knife-edge chain of `bench/knife_chain.py` (N knife edges on an inclined plane, "
             "neighbours coupled by springs; 3N coordinates, N first-order constraints "
             "x_i' sin θ_i − y_i' cos θ_i = 0; Chetaev's model; index-1 form with 7N states), "
             "integrated over [0, %s] at rtol %s, atol %s; and the paper's two examples "
             "(`examples/appell_hamel.toml`, `examples/particle.toml`, their own [simulate] settings)."
             % (env.get("t_end", "?"), env.get("rtol", "?"), env.get("atol", "?")))
    L.append("")

    # ---- the front end's scaling goals ----
    import report_goals
    L.extend(report_goals.goals(jdir, env, load, table, ratio, fmt_x))

    # ---- targets ----
    n_ref = 16
    a, p = nhc.get(n_ref), peers.get(n_ref)
    targets = []
    r_gen = ratio(p and p.get("derive_generate_s"), a and a.get("derive_analyse_generate_s"))
    targets.append(("N = 16: derive + generate ≥ 50× faster than SymPy (LagrangesMethod + lambdify)",
                    fmt_x(r_gen), r_gen is not None and r_gen >= 50))
    ops_j = a and a.get("residual_jacobian_joint_ops_after_cse")
    ops_js = p and p.get("residual_jacobian_ops_after_cse")
    ops_r = a and a.get("ops_by_function", {}).get("residual", [None, None])[1]
    ops_rs = p and p.get("residual_ops_after_cse")
    ok_ops = ops_j is not None and ops_js is not None and ops_j <= ops_js and ops_r <= ops_rs
    targets.append(("N = 16: operations after CSE ≤ sympy.cse (residual; residual + Jacobian)",
                    "%s vs %s; %s vs %s" % (ops_r, ops_rs, ops_j, ops_js), ok_ops))
    misses = []
    for label, d, sp in [(n, nhc.get(n), peers.get(n)) for n in peer_ns] + \
            [("Appell–Hamel", examples.get("appell_hamel"), peer_ah)]:
        if not d or not sp:
            continue
        mine = (d.get("ops_by_function", {}).get("residual", [None, None])[1],
                d.get("residual_jacobian_joint_ops_after_cse"))
        theirs = (sp.get("residual_ops_after_cse"), sp.get("residual_jacobian_ops_after_cse"))
        if None in mine or None in theirs:
            continue
        if mine[0] > theirs[0] or mine[1] > theirs[1]:
            misses.append("%s: %d vs %d; %d vs %d" % (label, mine[0], theirs[0], mine[1], theirs[1]))
    targets.append(("the same at every N of the peers and on Appell–Hamel (cases where nhc has more)",
                    "; ".join(misses) if misses else "none", not misses))
    r_int = None
    for method in ("Radau", "BDF"):
        m = p and p.get(method)
        r = ratio(m and m.get("integrate_s"), a and a.get("integrate_s"))
        if r is not None:
            r_int = r if r_int is None else min(r_int, r)
    targets.append(("N = 16: integration ≥ 100× faster than SciPy solve_ivp (Radau, BDF; the smaller ratio)",
                    fmt_x(r_int), r_int is not None and r_int >= 100))
    def hw_worst(cases):
        worst = None
        for d in cases:
            if not d or "handwritten_residual_call_s" not in d:
                continue
            for k in ("residual_call_s", "jacobian_call_s"):
                r = ratio(d.get(k), d.get("handwritten_" + k))
                if r is not None:
                    worst = r if worst is None else max(worst, r)
        return worst
    small = [nhc.get(n) for n in ns if n <= 16] + [examples.get("appell_hamel")]
    large = [nhc.get(n) for n in ns if n > 16]
    w_small, w_large = hw_worst(small), hw_worst(large)
    targets.append(("generated residual and Jacobian within 1.2× the hand-written: N ≤ 16 and Appell–Hamel "
                    "(worst of the two functions and all these cases)", fmt_x(w_small),
                    w_small is not None and w_small <= 1.2))
    if large:
        targets.append(("the same for N = %s" % ", ".join(str(n) for n in ns if n > 16), fmt_x(w_large),
                        w_large is not None and w_large <= 1.2))
    d64 = nhc.get(64)
    t64 = d64 and d64.get("derive_analyse_generate_s")
    targets.append(("N = 64 derived, analysed and generated in under 2 s", fmt_s(t64), t64 is not None and t64 < 2))
    slope = fit_slope([(n, nhc[n]["integrate_s"] / nhc[n]["steps"]) for n in ns
                       if n >= 8 and nhc.get(n) and nhc[n].get("steps")])
    targets.append(("integration cost per step ~ linear in N with KLU (log-log slope for N ≥ 8, "
                    "accepted in 0.7…1.3)", "%.2f" % slope if slope is not None else "–",
                    slope is not None and 0.7 <= slope <= 1.3))
    L.append("## Targets of the benchmark suite")
    L.append("")
    L.append(table(["target", "measured", "met"], [(t, m, "yes" if ok else "**no**") for t, m, ok in targets]))
    L.append("")

    # ---- nhc scaling ----
    L.append("## nhc on the knife-edge chain")
    L.append("")
    L.append("derive = scene → equations of Chetaev's model; analyse = Pryce's Σ-method and the index-1 "
             "reduction; generate = Jacobian, CSE and the header text. compile = the generated header "
             "with `-std=c++17 -O2 -fPIC -shared` (as `nhc simulate`). integrate = consistent "
             "initialization and IDA to t_end (dense LU below %s states, KLU from there: "
             "`nhc::default_jacobian_kind`). " % threshold +
             "Operations are nhc's count (+, −, ×, ÷, calls) of the whole header.")
    L.append("")
    rows = []
    for n in ns:
        d = nhc.get(n)
        if not d:
            rows.append((n, "failed") + ("",) * 12)
            continue
        per_step = d["integrate_s"] / d["steps"] if d.get("steps") else None
        rows.append((n, d["n_states"], fmt_s(d["derive_s"] + d["load_s"]), fmt_s(d["analyse_s"]),
                     fmt_s(d["generate_s"]), fmt_s(d["derive_analyse_generate_s"]), fmt_s(d["compile_s"]),
                     "%d / %d" % (d["ops_before_cse"], d["ops_after_cse"]), d["linear_solver"],
                     d["steps"], "%d / %d" % (d["residual_evaluations"], d["jacobian_evaluations"]),
                     fmt_s(d["integrate_s"]), fmt_s(per_step)))
    L.append(table(["N", "states", "derive", "analyse", "generate", "total", "compile", "ops before / after CSE",
                    "solver", "steps", "F / J evaluations", "integrate", "per step"], rows))
    L.append("")
    gen_slope = fit_slope([(n, nhc[n]["derive_analyse_generate_s"]) for n in ns if n >= 8 and nhc.get(n)])
    L.append("Log-log slopes for N ≥ 8: derive + analyse + generate %s, integration time per step %s."
             % ("%.2f" % gen_slope if gen_slope is not None else "–", "%.2f" % slope if slope is not None else "–"))
    L.append("")

    # ---- SymPy ----
    L.append("## Against SymPy (derivation, code generation, operation counts)")
    L.append("")
    L.append("SymPy: `LagrangesMethod(L, q, nonhol_coneqs=f)`, `form_lagranges_equations()`, "
             "`mass_matrix_full` and `forcing_full` (Lagrange's equations with multipliers, which for "
             "first-order constraints are Chetaev's), then `lambdify(..., cse=True)` of both (its code "
             "generation). Operation counts: `count_ops` of `sympy.cse`'s output (replacements and reduced "
             "expressions). *M, F*: the mass matrix and forcing as SymPy returns them; *residual*: "
             "M(y)·[q'; u'; λ] − F(y), the index-1 residual nhc generates; *residual + Jacobian*: that "
             "and dF/dy + cj·dF/dy', the same functions nhc generates, in one cse (nhc: its residual "
             "and Jacobian lowered into one DAG, counted the same way).")
    L.append("")
    rows = []
    for n in peer_ns:
        d, s = nhc.get(n), peers.get(n)
        if not s:
            rows.append((n, "failed or timed out") + ("",) * 8)
            continue
        ops_r_n = d and d.get("ops_by_function", {}).get("residual", [None, None])[1]
        rows.append((n, fmt_s(s["derive_s"]), fmt_s(s["lambdify_s"]), fmt_s(s["derive_generate_s"]),
                     fmt_s(d and d["derive_analyse_generate_s"]),
                     fmt_x(ratio(s["derive_generate_s"], d and d["derive_analyse_generate_s"])),
                     s["ops_after_cse"],
                     "%s / %s" % (s.get("residual_ops_after_cse", "–"), ops_r_n),
                     "%s / %s" % (s.get("residual_jacobian_ops_after_cse", "–"),
                                  d and d.get("residual_jacobian_joint_ops_after_cse"))))
    s = peer_ah
    d = examples.get("appell_hamel")
    if s and d:
        rows.append(("Appell–Hamel", fmt_s(s["derive_s"]), fmt_s(s["lambdify_s"]), fmt_s(s["derive_generate_s"]),
                     fmt_s(d["derive_analyse_generate_s"]),
                     fmt_x(ratio(s["derive_generate_s"], d["derive_analyse_generate_s"])), s["ops_after_cse"],
                     "%s / %s" % (s.get("residual_ops_after_cse", "–"),
                                  d.get("ops_by_function", {}).get("residual", [None, None])[1]),
                     "%s / %s" % (s.get("residual_jacobian_ops_after_cse", "–"),
                                  d.get("residual_jacobian_joint_ops_after_cse"))))
    L.append(table(["N", "SymPy derive", "lambdify", "SymPy total", "nhc derive + analyse + generate",
                    "speed-up", "ops M, F (SymPy)", "ops residual SymPy / nhc",
                    "ops residual + Jacobian SymPy / nhc"], rows))
    L.append("")
    L.append("nhc's total also covers the structural analysis, the Jacobian and the hidden constraints, "
             "which the SymPy column does not produce. The particle (paper, Example 1) has a second-order "
             "constraint, which `LagrangesMethod` does not accept: no SymPy/SciPy peer.")
    L.append("")

    # ---- SciPy ----
    L.append("## Integration against SciPy")
    L.append("")
    L.append("SciPy: `solve_ivp(method=Radau|BDF)` on q' = u, u' from M z = F (`numpy.linalg.solve` of "
             "the lambdified matrices at every evaluation; finite-difference Jacobian), same initial "
             "state, t_end, rtol and atol. nhc: IDA on the index-1 DAE with the generated Jacobian. "
             "max Δ = largest difference between nhc and SciPy over the coordinates and velocities at t_end.")
    L.append("")
    rows = []
    cases = [(n, nhc.get(n), peers.get(n)) for n in peer_ns] + [("Appell–Hamel", examples.get("appell_hamel"), peer_ah)]
    for label, d, s in cases:
        if not d or not s:
            continue
        row = [label, fmt_s(d["integrate_s"]), d["steps"]]
        for method in ("Radau", "BDF"):
            m = s.get(method)
            if not m:
                row += ["–", "–", "–", "–"]
                continue
            row += [fmt_s(m["integrate_s"]) + ("" if m["success"] else " (failed)"),
                    "%d / %d" % (m["steps"], m["nfev"]), fmt_x(ratio(m["integrate_s"], d["integrate_s"])),
                    "%.1e" % final_difference(d, m) if final_difference(d, m) is not None else "–"]
        rows.append(row)
    L.append(table(["N", "nhc", "nhc steps", "Radau", "Radau steps / f evals", "Radau / nhc", "max Δ Radau",
                    "BDF", "BDF steps / f evals", "BDF / nhc", "max Δ BDF"], rows))
    L.append("")

    # ---- hand-written ----
    L.append("## Generated against hand-written")
    L.append("")
    L.append("Hand-written headers following the same contract and state layout: "
             "`bench/knife_chain_handwritten.hpp` (loops over the knife edges, sin/cos once per edge) and "
             "`tests/runtime/handwritten/appell_hamel_chetaev.hpp`, compiled with the same flags and loaded "
             "the same way. One call at the consistent initial point (best of 9 batches, the two headers' "
             "batches interleaved); code bytes = machine code of the residual and Jacobian functions "
             "(`nm -S`; – where the library is stripped, as nhc::jit builds them with `-s`). The Jacobian is the one the integrator used (dense below %s states, compressed-column values "
             "from there). " % threshold +
             "max Δ = largest difference between the final states of the two runs; it is not 0 because the "
             "two libraries are different objects (nhc::jit builds them with hidden visibility, so equal "
             "namespaces cannot alias; the compared-objects column shows both tables).")
    L.append("")
    rows = []
    out_dir = os.path.dirname(os.path.abspath(jdir))
    hw_cases = [(n, nhc.get(n), os.path.join(out_dir, "nhc", str(n))) for n in ns] + \
        [("Appell–Hamel", examples.get("appell_hamel"), os.path.join(out_dir, "nhc", "appell_hamel"))]
    for label, d, lib_dir in hw_cases:
        if not d or "handwritten_residual_call_s" not in d:
            continue
        cache = os.path.join(lib_dir, "jit-cache")
        gen_lib = os.path.join(cache, d.get("generated_library", ""))
        hw_lib = os.path.join(cache, d.get("handwritten_library", ""))
        gen_bytes = code_bytes(gen_lib) if os.path.isfile(gen_lib) else None
        hw_bytes = code_bytes(hw_lib) if os.path.isfile(hw_lib) else None
        distinct = distinct_objects(d, gen_lib, hw_lib)
        rows.append((label, fmt_s(d["residual_call_s"]), fmt_s(d["handwritten_residual_call_s"]),
                     fmt_x(ratio(d["residual_call_s"], d["handwritten_residual_call_s"])),
                     fmt_s(d["jacobian_call_s"]), fmt_s(d["handwritten_jacobian_call_s"]),
                     fmt_x(ratio(d["jacobian_call_s"], d["handwritten_jacobian_call_s"])),
                     fmt_s(d["integrate_s"]), fmt_s(d["handwritten_integrate_s"]),
                     fmt_x(ratio(d["integrate_s"], d["handwritten_integrate_s"])),
                     "%d / %d" % (d["steps"], d["handwritten_steps"]),
                     "%.1e" % d["handwritten_final_difference"], fmt_s(d["compile_s"]),
                     fmt_s(d["handwritten_compile_s"]),
                     "%s / %s" % (gen_bytes if gen_bytes else "–", hw_bytes if hw_bytes else "–"), distinct))
    L.append(table(["N", "residual", "hand", "ratio", "Jacobian", "hand", "ratio", "integrate", "hand", "ratio",
                    "steps gen / hand", "max Δ", "compile", "compile hand", "code bytes gen / hand",
                    "compared objects (library: table address)"], rows))
    L.append("")

    # ---- examples ----
    L.append("## The paper's examples")
    L.append("")
    rows = []
    for name, d in examples.items():
        if not d:
            rows.append((name, "failed") + ("",) * 7)
            continue
        rows.append((name, d["model"], d["n_states"], fmt_s(d["derive_analyse_generate_s"]), fmt_s(d["compile_s"]),
                     "%d / %d" % (d["ops_before_cse"], d["ops_after_cse"]), d["steps"],
                     "%d / %d" % (d["residual_evaluations"], d["jacobian_evaluations"]), fmt_s(d["integrate_s"])))
    L.append(table(["scene", "model", "states", "derive + analyse + generate", "compile", "ops before / after CSE",
                    "steps", "F / J evaluations", "integrate"], rows))
    L.append("")

    # ---- plot ----
    with open(plot_data, "w") as f:
        f.write("# N nhc_generate nhc_compile nhc_integrate handwritten_integrate sympy_derive_generate "
                "scipy_radau scipy_bdf\n")
        for n in ns:
            d, s = nhc.get(n), peers.get(n)
            if not d:
                continue

            def v(x):
                return "%.6g" % x if x else "NaN"
            f.write("%d %s %s %s %s %s %s %s\n" % (
                n, v(d["derive_analyse_generate_s"]), v(d["compile_s"]), v(d["integrate_s"]),
                v(d.get("handwritten_integrate_s")), v(s and s["derive_generate_s"]),
                v(s and s.get("Radau", {}).get("integrate_s")), v(s and s.get("BDF", {}).get("integrate_s"))))
    L.append("## Time against N")
    L.append("")
    L.append("![time against N](results-time.svg)")
    L.append("")
    plot_txt = os.path.join(jdir, "plot.txt")
    if os.path.exists(plot_txt):
        with open(plot_txt) as f:
            L.append("```")
            L.append(f.read().rstrip("\n"))
            L.append("```")
            L.append("")

    whipple = os.path.join(jdir, "whipple.md")
    if os.path.exists(whipple):
        L.append("## The Whipple bicycle beside SymPy's Kane's method")
        L.append("")
        L.append("bench/whipple_sympy.py, in this run: SymPy's own bicycle (`test_kane3.test_bicycle` up to "
                 "`kanes_equations`, then `sympy.cse` of the mass matrix and forcing) and nhc cold "
                 "(scene cache off, an empty compile cache) on examples/whipple/whipple_bicycle.toml.")
        L.append("")
        with open(whipple) as f:
            L.append(f.read().rstrip("\n"))
        L.append("")

    notes_path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "notes.md")
    if os.path.exists(notes_path):
        with open(notes_path) as f:
            L.append(f.read().rstrip("\n"))
            L.append("")

    with open(results_path + ".tmp", "w") as f:
        f.write("\n".join(L) + "\n")
    os.replace(results_path + ".tmp", results_path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
