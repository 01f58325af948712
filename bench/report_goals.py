"""The front end's goals in bench/results.md: the goal table (met / not met), the front end's scaling
(cold, per command), the scene-cache warm simulate and the second family. Every number comes
from this run's JSON files (bench/run.sh: frontend_*.json from bench/frontend_scaling.py,
nhc_*.json from nhc_bench, peers_*.json from bench/peers.py)."""
import os


def _load(load, jdir, name):
    return load(os.path.join(jdir, name))


def _s(v):
    return "–" if v is None else ("%.0f" % v if v >= 100 else "%.2f" % v if v >= 0.1 else "%.3f" % v)


def _verdict(ok, measured_at_goal=True):
    if not measured_at_goal:
        return "not measured (see the value)"
    return "met" if ok else "**not met**"


def front_end_table(fe, table):
    rows = []
    for r in fe.get("rows", []):
        if r.get("status") == "ok":
            rows.append((r["n"], _s(r["derive_s"]), _s(r["analyze_s"]), _s(r["generate_s"]), _s(r["front_end_s"]),
                         "%.0f" % r["peak_mb"], "ok"))
        else:
            rows.append((r["n"], "–", "–", "–", "–", "–", r.get("status", "?") +
                         (": " + r["error"] if r.get("error") else "")))
    return table(["N", "derive", "analyze", "generate", "front end (`nhc generate`)", "peak MB", "status"], rows)


def goals(jdir, env, load, table, ratio, fmt_x):
    """Returns the markdown lines of the issue-17 sections."""
    L = []
    fe = _load(load, jdir, "frontend_knife_chain_chetaev.json") or {}
    rows = {r["n"]: r for r in fe.get("rows", [])}
    nhc_ns = env.get("nhc_N", [])
    nhc = {n: _load(load, jdir, "nhc_knife_chain_%d.json" % n) for n in nhc_ns}
    goal_rows = []

    # 1. slope of the front end, N = 64 ... 1024 (least squares on log-log).
    fit, fit_ns = fe.get("slope_64_1024"), fe.get("slope_64_1024_ns", [])
    at_goal = 64 in fit_ns and 1024 in fit_ns
    r1024 = rows.get(1024)
    if r1024 is not None and r1024.get("status") != "ok":
        at_goal, fit = True, None  # N = 1024 was tried and did not finish: the goal is not met
    goal_rows.append(("front end (derive + analyze + generate) log-log slope ≤ 1.1, N = 64 … 1024",
                      "%s (least squares over N = %s)" % ("%.2f" % fit if fit is not None else "–",
                                                         ", ".join(map(str, fit_ns)) or "none"),
                      _verdict(fit is not None and fit <= 1.1, at_goal)))
    # 2, 3. N = 1024 under 10 s and 500 MB.
    r = rows.get(1024)
    if r is None:
        goal_rows.append(("N = 1024 front end under 10 s", "N = 1024 not in this run", _verdict(False, False)))
        goal_rows.append(("N = 1024 front end under 500 MB", "N = 1024 not in this run", _verdict(False, False)))
    elif r.get("status") != "ok":
        goal_rows.append(("N = 1024 front end under 10 s", r.get("status"), "**not met**"))
        goal_rows.append(("N = 1024 front end under 500 MB", r.get("status"), "**not met**"))
    else:
        goal_rows.append(("N = 1024 front end under 10 s", "%.2f s" % r["front_end_s"],
                          _verdict(r["front_end_s"] < 10)))
        goal_rows.append(("N = 1024 front end under 500 MB", "%.0f MB (the largest of the three commands)"
                          % r["peak_mb"], _verdict(r["peak_mb"] < 500)))
    # 4. warm simulate at N = 512.
    w = fe.get("warm_simulate")
    if not w:
        goal_rows.append(("scene-cache warm `nhc simulate`, N = 512: under 0.5 s + integration", "not measured",
                          _verdict(False, False)))
    else:
        warm = w.get("warm", {})
        if warm.get("status") == "ok":
            over = warm["wall_s"] - warm["integrate_s"]
            goal_rows.append(("scene-cache warm `nhc simulate`, N = 512: under 0.5 s + integration",
                              "N = %d: %.2f s wall − %.3f s integrate = %.2f s (derive %.3f s%s, compile %.3f s%s)"
                              % (w["n"], warm["wall_s"], warm["integrate_s"], over, warm["derive_s"],
                                 " scene cache" if warm.get("scene_cache") else " **not from the scene cache**",
                                 warm["compile_s"], " cached" if warm.get("compile_cached") else ""),
                              _verdict(over < 0.5 and warm.get("scene_cache"), w["n"] >= 512)))
        else:
            bad = warm if warm else w.get("cold", {})
            goal_rows.append(("scene-cache warm `nhc simulate`, N = 512: under 0.5 s + integration",
                              "N = %d: %s %s" % (w["n"], bad.get("status", "?"), bad.get("error", "")),
                              "**not met**"))
    # 5. compile within 2x hand-written at N = 64.
    d = nhc.get(64)
    rc = ratio(d and d.get("compile_s"), d and d.get("handwritten_compile_s"))
    goal_rows.append(("compile within 2× the hand-written chain's at N = 64",
                      "%s (%s s vs %s s)" % (fmt_x(rc), _s(d and d.get("compile_s")),
                                             _s(d and d.get("handwritten_compile_s"))) if rc else "N = 64 not measured",
                      _verdict(rc is not None and rc <= 2, rc is not None)))
    # 6. run time within 1.2x hand-written at every N.
    worst, worst_n, missing = None, None, []
    for n in nhc_ns:
        d = nhc.get(n)
        r_run = ratio(d and d.get("integrate_s"), d and d.get("handwritten_integrate_s"))
        if r_run is None:
            missing.append(n)
        elif worst is None or r_run > worst:
            worst, worst_n = r_run, n
    goal_rows.append(("run time (consistent initialization + IDA) within 1.2× hand-written at every N",
                      "worst %s at N = %s (N = %s; compile + run stops at N = %s)%s"
                      % (fmt_x(worst), worst_n, ", ".join(map(str, nhc_ns)), max(nhc_ns) if nhc_ns else "–",
                         "; failed at N = " + ", ".join(map(str, missing)) if missing else ""),
                      _verdict(worst is not None and worst <= 1.2 and not missing, worst is not None)))
    # 7. CSE op count <= sympy.cse on every case.
    cases, misses = 0, []
    for label, dn, sp in [(n, nhc.get(n), _load(load, jdir, "peers_%d.json" % n)) for n in env.get("peer_N", [])] + \
            [("Appell–Hamel", _load(load, jdir, "nhc_appell_hamel.json"), _load(load, jdir, "peers_appell_hamel.json"))]:
        if not dn or not sp:
            continue
        mine = (dn.get("ops_by_function", {}).get("residual", [None, None])[1],
                dn.get("residual_jacobian_joint_ops_after_cse"))
        theirs = (sp.get("residual_ops_after_cse"), sp.get("residual_jacobian_ops_after_cse"))
        if None in mine or None in theirs:
            continue
        cases += 1
        if mine[0] > theirs[0] or mine[1] > theirs[1]:
            misses.append("%s: %d vs %d; %d vs %d" % (label, mine[0], theirs[0], mine[1], theirs[1]))
    goal_rows.append(("operations after CSE ≤ sympy.cse on every case (residual; residual + Jacobian)",
                      "%d cases; more than sympy.cse: %s" % (cases, "; ".join(misses) if misses else "none"),
                      _verdict(not misses, cases > 0)))

    L.append("## The front end's goals")
    L.append("")
    L.append("Knife-edge chain, Chetaev. The front end is measured cold (`NHC_SCENE_CACHE=off`, a fresh cache "
             "directory) as the three commands `nhc derive`, `nhc analyze`, `nhc generate`, each limited to "
             "%g s (`bench/frontend_scaling.py`); compile and run come from `nhc_bench` with the hand-written "
             "chain (`bench/knife_chain_handwritten.hpp`) for N = %s only. %s"
             % (env.get("stage_timeout_s", float("nan")), ", ".join(map(str, nhc_ns)),
                "**Quick run (`--quick`): small N, the goals at N = 512 and 1024 are not measured.**"
                if env.get("quick") else ""))
    L.append("")
    L.append(table(["goal", "measured", ""], goal_rows))
    L.append("")
    L.append("## The front end's goals: scaling (knife-edge chain, Chetaev, cold)")
    L.append("")
    L.append("Wall seconds. Each command runs the pipeline up to its stage: derive = `nhc derive`, analyze = "
             "`nhc analyze` − `nhc derive`, generate = `nhc generate` − `nhc analyze` (differences of separate "
             "processes, so small ones are noisy); the front end = `nhc generate` alone. peak MB = the largest "
             "resident set of the three. A command over its time limit is \"timed out\" and the larger N are skipped.")
    L.append("")
    L.append(front_end_table(fe, table))
    L.append("")
    if fe.get("slope_all") is not None:
        L.append("Log-log slope (least squares) of the front end: %.2f over N = %s."
                 % (fe["slope_all"], ", ".join(map(str, fe.get("slope_all_ns", [])))))
        L.append("")
    w = fe.get("warm_simulate")
    if w:
        L.append("`nhc simulate` at N = %d with the scene cache on (a fresh cache directory), from simulate's own "
                 "`time:` line; wall from the harness (the run writes its CSV, every state at the scene's "
                 "default outputs):" % w["n"])
        L.append("")
        wr = []
        for run in ("cold", "warm"):
            e = w.get(run)
            if not e:
                continue
            if e.get("status") == "ok":
                rest = e["wall_s"] - e["derive_s"] - e["compile_s"] - e["integrate_s"]
                wr.append((run, _s(e["wall_s"]), "%s%s" % (_s(e["derive_s"]), " (scene cache)" if e["scene_cache"] else ""),
                           "%s%s" % (_s(e["compile_s"]), " (cached)" if e["compile_cached"] else ""),
                           _s(e["integrate_s"]), _s(rest), "%.0f" % e["peak_mb"], "ok"))
            else:
                wr.append((run, _s(e["wall_s"]), "–", "–", "–", "–", "–", e["status"] + " " + e.get("error", "")))
        L.append(table(["run", "wall", "derive", "compile", "integrate",
                        "rest (start, scene, load, check, CSV, drift)", "peak MB", "status"], wr))
        L.append("")

    L.append("## The front end's goals: the second family")
    L.append("")
    L.append("The particle chain (`bench/particle_chain.py`: N planar particles, x_i'x_i'' + y_i'y_i'' = 0, "
             "neighbours coupled by springs; Chetaev) and the knife-edge chain under the vakonomic model. "
             "Front end cold as above; compile and run from `nhc_bench` (no hand-written code for these).")
    L.append("")
    for family, model, prefix in (("particle_chain", "chetaev", "nhc_particle_chain_%d.json"),
                                  ("knife_chain", "vakonomic", "nhc_knife_chain_vakonomic_%d.json")):
        fe2 = _load(load, jdir, "frontend_%s_%s.json" % (family, model))
        L.append("### %s, %s" % (family.replace("_", " "), model))
        L.append("")
        if not fe2:
            L.append("frontend_scaling.py produced no result.")
            L.append("")
        else:
            L.append(front_end_table(fe2, table))
            L.append("")
            if fe2.get("slope_all") is not None:
                L.append("Log-log slope (least squares) of the front end: %.2f over N = %s."
                         % (fe2["slope_all"], ", ".join(map(str, fe2.get("slope_all_ns", [])))))
                L.append("")
        cr = []
        for n in env.get("family2_N", []):
            d = _load(load, jdir, prefix % n)
            if not d:
                why = "no result"
                try:
                    with open(os.path.join(jdir, (prefix % n)[:-len(".json")] + ".status")) as f:
                        why = f.read().strip()
                except OSError:
                    pass
                cr.append((n, "–", "–", "–", "–", "–", why))
                continue
            cr.append((n, d["n_states"], _s(d["derive_analyse_generate_s"]), _s(d["compile_s"]), d["steps"],
                       _s(d["integrate_s"]), "ok"))
        L.append(table(["N", "states", "derive + analyse + generate (nhc_bench)", "compile", "steps", "integrate",
                        "status"], cr))
        L.append("")
    L += rigid_body_family(_load(load, jdir, "frontend_rolling_balls_chetaev.json"), table)
    return L


def rigid_body_family(fe, table):
    """A family of rigid bodies: N rolling balls, every body quantity a definition."""
    L = ["## A family of rigid bodies", "",
         "N uniform balls rolling without slipping on a plane, neighbours' centres joined by springs "
         "(`bench/rolling_balls.py`: Euler angles, each ball's rotation, angular velocity, centre, velocity, "
         "kinetic energy and contact-point velocity written as definitions, as examples/rolling_ball.toml writes "
         "one ball; 5N coordinates, 2N constraints; Chetaev). Front end cold as above; operations after CSE and "
         "bytes of the whole header `nhc generate` writes; cold `nhc simulate` = derive, compile and the "
         "scene's 1 s of motion with nothing cached. SymPy models no such scene in its tests: no peer column.", ""]
    if not fe:
        return L + ["frontend_scaling.py produced no result.", ""]
    rows = []
    for r in fe.get("rows", []):
        if r.get("status") != "ok":
            rows.append((r["n"], 5 * r["n"], "–", "–", "–", "–", "–", "–", "–", r.get("status", "?")))
            continue
        sim = r.get("simulate")
        sim_text = "–" if not sim else (_s(sim["wall_s"]) + " s, %.0f MB" % sim["peak_mb"] if sim["status"] == "ok"
                                        else sim["status"] + (": " + sim["error"] if sim.get("error") else ""))
        ops = r.get("ops_after_cse")
        rows.append((r["n"], 5 * r["n"], _s(r["derive_s"]), _s(r["front_end_s"]), "%.0f" % r["peak_mb"],
                     "–" if ops is None else "{:,}".format(ops),
                     "–" if ops is None else "%.0f" % (ops / r["n"]),
                     "–" if r.get("header_bytes") is None else "%.0f" % (r["header_bytes"] / 1024), sim_text, "ok"))
    L.append(table(["N", "coordinates", "derive", "front end (`nhc generate`)", "peak MB", "operations after CSE",
                    "per ball", "header kB", "cold `nhc simulate`", "status"], rows))
    L.append("")
    if fe.get("slope_all") is not None:
        L.append("Log-log slope (least squares) of the front end: %.2f over N = %s."
                 % (fe["slope_all"], ", ".join(map(str, fe.get("slope_all_ns", [])))))
        L.append("")
    return L
