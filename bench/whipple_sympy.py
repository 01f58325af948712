#!/usr/bin/env python3
"""The Whipple bicycle benchmark (Meijaard et al., Proc. R. Soc. A 463 (2007), Table 2), nhc beside
SymPy's Kane's method on the same bicycle, in one run:

- SymPy: the body of `sympy.physics.mechanics.tests.test_kane3.test_bicycle` up to
  `kanes_equations`, then `sympy.cse` of the mass matrix and forcing; operations counted by
  `sympy.count_ops` and by nhc's own rules (count_as_nhc below, after codegen/nhc/expr/expression_dag.cpp);
- nhc, cold (scene cache off, an empty compile cache): `nhc generate` (time, operations of the
  residual and of the whole header after CSE, header bytes), `nhc simulate` (derive, compile, 5 s of
  motion; time and peak memory), `nhc linearize --at "phi'=0"` (eigenvalues against Table 2) and a
  101-point sweep of v over [0, 10] with both thresholds refined (against Table 2's speeds).

The two times compared (nhc generate; SymPy's kanes_equations + cse) are each the best of three
fresh processes: single runs of either vary by half on a shared machine (0.24 to 0.40 s and 3.3 to
5.7 s were seen), and the best of several is the least disturbed. SymPy runs in a new interpreter
each time (`--sympy-json`), so that no run finds the expressions of another in SymPy's cache.

Usage: bench/whipple_sympy.py [NHC] [SCENE] [--markdown=FILE]   (defaults: build/cli/nhc,
examples/whipple/whipple_bicycle.toml). Without SymPy (Debian python3-sympy) the SymPy part is
skipped with a message; nhc is still measured.
"""
import inspect
import json
import os
import re
import subprocess
import sys
import tempfile
import textwrap
import time

REPEATS = 3  # fresh processes per compared time, the best taken
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Table 2 of Meijaard et al. (2007), v = 5 m/s: castering, weave pair, capsize; and the speeds.
TABLE2 = [complex(-14.07838969279822, 0), complex(-0.77534188219585, 4.46486771378823),
          complex(-0.77534188219585, -4.46486771378823), complex(-0.32286642900409, 0)]
WEAVE, CAPSIZE = 4.29238253634111, 6.02426201538837


def run_timed(command, env):
    """Wall seconds, peak resident kB of the command (and its children), stdout."""
    start = time.perf_counter()
    done = subprocess.run(["/usr/bin/time", "-f", "%M"] + command, env=env, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} exited {done.returncode}: {done.stderr[-500:]}")
    peak = int(done.stderr.strip().splitlines()[-1])
    return seconds, peak, done.stdout


def header_counts(path):
    text = open(path).read()
    counts = {}
    for name, before, after in re.findall(r"^//   (\w+)\s+(\d+)\s+(\d+)$", text, re.M):
        counts[name] = (int(before), int(after))
    return counts, len(text.encode())


def measure_nhc(nhc, scene):
    work = tempfile.mkdtemp(prefix="nhc-whipple-")
    env = dict(os.environ, NHC_CACHE_DIR=os.path.join(work, "cache"), NHC_SCENE_CACHE="off")
    out = {}
    runs = [run_timed([nhc, "generate", scene, "--quiet", "-o", os.path.join(work, "header")], env)
            for _ in range(REPEATS)]
    out["generate_seconds"] = min(r[0] for r in runs)
    out["generate_peak_kb"] = max(r[1] for r in runs)
    header = [f for f in os.listdir(os.path.join(work, "header")) if f.endswith(".hpp")][0]
    out["counts"], out["header_bytes"] = header_counts(os.path.join(work, "header", header))
    out["simulate_seconds"], out["simulate_peak_kb"], _ = run_timed(
        [nhc, "simulate", scene, "-o", os.path.join(work, "run.csv")], env)
    out["linearize_seconds"], _, text = run_timed([nhc, "linearize", scene, "--at", "phi'=0", "--format", "json"], env)
    eigenvalues = [complex(e["re"], e["im"]) for e in json.loads(text)["eigenvalues"]]
    out["eigenvalue_difference"] = max(
        abs(min(eigenvalues, key=lambda e: abs(e - want)) - want) / abs(want) for want in TABLE2)
    out["sweep_seconds"], _, text = run_timed(
        [nhc, "linearize", scene, "--at", "phi'=0", "--sweep", "v=0:10:101", "--format", "json"], env)
    speeds = [t["value"] for t in json.loads(text)["thresholds"]]
    out["thresholds"] = speeds
    out["speed_difference"] = max(abs(min(speeds, key=lambda s: abs(s - want)) - want) for want in (WEAVE, CAPSIZE))
    return out


def count_as_nhc(expressions):
    """Floating-point operations of expression trees as nhc's code generator counts its own
    (instruction_cost in codegen/nhc/expr/expression_dag.cpp): an n-ary sum n − 1 additions, a product
    n − 1 multiplications (a coefficient ±1 is free, a negative sign absorbed), x^k (k ≤ 4) k − 1
    multiplications, one division per quotient, sqrt and other functions one call."""
    import sympy

    def cost(e):
        if e.is_Atom:
            return 0
        if e.is_Add:
            return len(e.args) - 1 + sum(cost(a) for a in e.args)
        if e.is_Mul:
            numerator, denominator, total = [], [], 0
            for f in e.args:
                if f.is_Number:
                    if abs(f) != 1:
                        numerator.append(f)
                    continue
                if f.is_Pow and f.exp.is_Number and f.exp < 0:
                    denominator.append(sympy.Pow(f.base, -f.exp))
                else:
                    numerator.append(f)
            total += sum(cost(f) for f in numerator) + max(len(numerator) - 1, 0)
            if denominator:
                total += sum(cost(f) for f in denominator) + len(denominator) - 1 + 1
            return total
        if e.is_Pow:
            base, exp = e.base, e.exp
            if exp.is_Integer:
                k = abs(int(exp))
                power = k - 1 if k <= 4 else 1
                return cost(base) + power + (1 if exp < 0 else 0)
            if exp.is_Rational and exp.q == 2:
                whole = (abs(exp.p) - 1) // 2
                power = 0 if whole == 0 else (whole - 1 if whole <= 4 else 1) + 1
                return cost(base) + 1 + power + (1 if exp < 0 else 0)
            return cost(base) + cost(exp) + 1
        return 1 + sum(cost(a) for a in e.args)

    return sum(cost(e) for e in expressions)


def measure_sympy():
    try:
        import sympy
        from sympy.physics.mechanics.tests import test_kane3
    except ImportError:
        return None
    source = inspect.getsource(test_kane3.test_bicycle).splitlines()
    start = next(i for i, line in enumerate(source) if line.startswith("def "))
    end = next(i for i, line in enumerate(source) if "kanes_equations" in line)
    body = textwrap.dedent("\n".join(source[start + 1:end + 1]))
    namespace = dict(vars(test_kane3))
    t0 = time.perf_counter()
    exec(body, namespace)  # the test's own text up to KM.kanes_equations(BL, FL)
    t1 = time.perf_counter()
    km = namespace["KM"]
    expressions = list(km.mass_matrix) + list(km.forcing)
    replacements, reduced = sympy.cse(expressions)
    t2 = time.perf_counter()
    shared = [e for _, e in replacements] + list(reduced)
    return {"version": sympy.__version__, "kane_seconds": t1 - t0, "cse_seconds": t2 - t1,
            "count_ops": sum(sympy.count_ops(e) for e in shared), "nhc_rules": count_as_nhc(shared)}


def measure_sympy_best():
    """measure_sympy() in REPEATS fresh interpreters; the run with the least kanes_equations + cse."""
    best = None
    for _ in range(REPEATS):
        done = subprocess.run([sys.executable, os.path.abspath(__file__), "--sympy-json"], capture_output=True,
                              text=True)
        if done.returncode != 0:
            raise RuntimeError("the SymPy run failed: " + done.stderr[-500:])
        result = json.loads(done.stdout)
        if result is None:
            return None
        if best is None or result["kane_seconds"] + result["cse_seconds"] < best["kane_seconds"] + best["cse_seconds"]:
            best = result
    return best


def markdown(nhc, sympy_result):
    c = nhc["counts"]
    lines = ["| quantity | nhc | SymPy (Kane, then cse of mass matrix and forcing) |", "|---|---|---|"]
    s = sympy_result
    lines.append(f"| operations after CSE, equations of motion | residual {c['residual'][1]:,} | "
                 + (f"{s['count_ops']:,} by count_ops, {s['nhc_rules']:,} by nhc's rules |" if s else "— |"))
    lines.append(f"| operations after CSE, whole header | {c['total'][1]:,} (residual, Jacobian, hidden constraints and "
                 f"their Jacobian, invariants) | — |")
    lines.append(f"| header | {nhc['header_bytes']:,} bytes | — |")
    lines.append(f"| equations to compact code, cold (best of {REPEATS} processes each) | "
                 f"`nhc generate` {nhc['generate_seconds']:.2f} s | "
                 + (f"kanes_equations {s['kane_seconds']:.2f} s + cse {s['cse_seconds']:.2f} s |" if s else "— |"))
    lines.append(f"| cold `nhc simulate` (derive, compile, 5 s of motion) | {nhc['simulate_seconds']:.2f} s, "
                 f"peak {nhc['simulate_peak_kb'] / 1024:.0f} MB | — |")
    lines.append(f"| `nhc linearize --at \"phi'=0\"` | {nhc['linearize_seconds']:.2f} s, eigenvalues within "
                 f"{nhc['eigenvalue_difference']:.1e} of Table 2 | — |")
    lines.append(f"| 101-point sweep of v over [0, 10], both thresholds refined | {nhc['sweep_seconds']:.2f} s, speeds "
                 f"within {nhc['speed_difference']:.1e} of Table 2 | — |")
    return "\n".join(lines) + "\n"


def main():
    if "--sympy-json" in sys.argv[1:]:
        print(json.dumps(measure_sympy()))
        return
    args = [a for a in sys.argv[1:] if not a.startswith("--markdown")]
    target = next((a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith("--markdown=")), None)
    nhc = args[0] if args else os.path.join(ROOT, "build", "cli", "nhc")
    scene = args[1] if len(args) > 1 else os.path.join(ROOT, "examples", "whipple", "whipple_bicycle.toml")
    sympy_result = measure_sympy_best()
    if sympy_result is None:
        print("SymPy not installed (Debian python3-sympy): its part is skipped")
    else:
        print(f"SymPy {sympy_result['version']}: kanes_equations {sympy_result['kane_seconds']:.2f} s, "
              f"cse {sympy_result['cse_seconds']:.2f} s, operations {sympy_result['count_ops']} (count_ops), "
              f"{sympy_result['nhc_rules']} (nhc's rules)")
    result = measure_nhc(nhc, scene)
    print(json.dumps({k: v for k, v in result.items()}, indent=1))
    table = markdown(result, sympy_result)
    print(table)
    if target:
        with open(target, "w") as out:
            out.write(table)


if __name__ == "__main__":
    main()
