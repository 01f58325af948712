#!/usr/bin/env python3
"""Issue 44: no scene may hang nhc. Generates a seeded family of absurd two-coordinate scenes
(Lagrangians under 200 characters: powers of sums, towers of powers, trigonometric functions of
sums raised to powers, reciprocals of sums, definitions that square the previous one) and runs
`nhc derive`, `nhc derive --format latex` and `nhc generate` on each with a time limit, recording
exit codes, the worst wall time and the worst peak memory (getrusage of the child). Every run must
end with exit 0, 2 or 3 within 5 s; the exit status is 1 when one does not.

Usage: bench/absurd_scenes.py NHC [--count 200] [--seed 44] [--limit 5] [--markdown FILE]
"""
import argparse
import os
import random
import resource
import subprocess
import sys
import tempfile
import time

TEMPLATES = [
    "({a}+{b}+{c})^{n}*({d}+{e})^-{n}*({f}+{a})^{m}",
    "{a}^-2^{b}*({c}^2+{d}^3)^{n}*({e}^3+{f}^-1)^{n}",
    "{a}^{b}^{c}^{d}^({e}+{f})^{m}",
    "sin({a}+{b}+{c})^{n}*cos({d}-{e}+{f})^{n}",
    "(sin({a}+{b})+cos({c}+{d})+{e}^-1)^{n}*({f}+{a})^{m}",
    "({a}+{b}+{c}+{d})^-{n}*({e}-{f}+{a})^{n}",
    "1/({a}+1/({b}+1/({c}+1/({d}+{e}))))^{n}",
    "(({a}+{b})^3+({c}+{d})^3)^{m}*(({e}+{f})^2+{a}^2)^-{m}",
    "({a}^-1+{b}^-1+{c}^-1+{d}^-1)^{n}*({e}+{f})^2",
    "exp(({a}+{b}+{c})^{m})*({d}+{e})^{n}",
    "sqrt({a}^2+{b}^2)*(({c}+{d}+{e})^{m}+1)^{m}",
]
ATOMS = ["x", "y", "x'", "y'", "sin(x)", "cos(y)", "x'^-1", "y'^-1", "t", "2"]


def lagrangian(rng):
    while True:
        kw = {k: rng.choice(ATOMS) for k in "abcdef"}
        kw["n"] = rng.randint(4, 30)
        kw["m"] = rng.randint(2, 12)
        text = rng.choice(TEMPLATES).format(**kw)
        if "x'" in text and len(text) < 200:
            return text


def squared_definitions(depth):
    lines = ["[definitions]", "d0 = \"x + x'\""]
    lines += [f"d{k} = \"d{k-1}*d{k-1} + x\"" for k in range(1, depth + 1)]
    return f"x'^2/2 - d{depth}", "\n".join(lines) + "\n"


def scene_text(lagr, extra=""):
    return ('name = "absurd"\ncoordinates = ["x", "y"]\n'
            f"lagrangian = '''{lagr}'''\n[initial]\nx = [0.1, 1.0]\ny = [0.2, 0.5]\n" + extra)


def run(cmd, limit):
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    start = time.monotonic()
    try:
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=limit * 4)
        code, err = p.returncode, p.stderr.decode(errors="replace").strip().splitlines()
    except subprocess.TimeoutExpired:
        code, err = "timeout", []
    elapsed = time.monotonic() - start
    # ru_maxrss of the children is the largest so far: it tells only when a run set a new maximum.
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return code, elapsed, peak if peak > before else 0, err[-1] if err else ""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("nhc")
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--seed", type=int, default=44)
    ap.add_argument("--limit", type=float, default=5.0)
    ap.add_argument("--markdown")
    args = ap.parse_args()
    rng = random.Random(args.seed)
    commands = {"derive": ["derive"], "derive --format latex": ["derive", "--format", "latex"],
                "generate": ["generate", "-q"]}
    stats = {name: {"codes": {}, "worst": (0.0, ""), "rss": 0, "bad": []} for name in commands}
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(args.count):
            if i % 10 == 9:
                lagr, extra = squared_definitions(rng.randint(20, 96))
            else:
                lagr, extra = lagrangian(rng), ""
            path = os.path.join(tmp, f"absurd_{i:03d}.toml")
            with open(path, "w") as f:
                f.write(scene_text(lagr, extra))
            for name, sub in commands.items():
                cmd = [args.nhc] + sub + [path] + (["-o", tmp] if sub[0] == "generate" else [])
                code, elapsed, rss, last = run(cmd, args.limit)
                s = stats[name]
                s["codes"][code] = s["codes"].get(code, 0) + 1
                if elapsed > s["worst"][0]:
                    s["worst"] = (elapsed, lagr)
                s["rss"] = max(s["rss"], rss)
                print(f"run {name} #{i}: exit {code} in {elapsed:.2f} s, peak {rss / 1024:.0f} MB", flush=True)
                if code not in (0, 2, 3) or elapsed > args.limit:
                    s["bad"].append((i, code, elapsed, lagr, last))
                    print(f"FAIL {name} #{i}: exit {code} in {elapsed:.2f} s: {lagr}: {last}", file=sys.stderr)
    sys.stdout.flush()
    rows = ["| command | scenes | exit codes | worst time (s) | worst peak memory (MB) | over the limit |",
            "|---|---|---|---|---|---|"]
    for name, s in stats.items():
        codes = ", ".join(f"{k}: {v}" for k, v in sorted(s["codes"].items(), key=lambda kv: str(kv[0])))
        rows.append(f"| `nhc {name}` | {args.count} | {codes} | {s['worst'][0]:.2f} | {s['rss'] / 1024:.0f} | "
                    f"{len(s['bad'])} |")
    table = "\n".join(rows)
    print(table)
    for name, s in stats.items():
        print(f"slowest under nhc {name} ({s['worst'][0]:.2f} s): {s['worst'][1]}")
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(table + "\n")
    return 1 if any(s["bad"] for s in stats.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
