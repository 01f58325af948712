#!/usr/bin/env python3
"""No scene may hang nhc. Generates a seeded family of absurd two-coordinate scenes
(Lagrangians under 200 characters: powers of sums, towers of powers, trigonometric functions of
sums raised to powers, reciprocals of sums, definitions that square the previous one) and runs
`nhc derive`, `nhc derive --format latex` and `nhc generate` on each with a time limit, recording
exit codes, the worst wall time, the worst processor time (user + system) and the worst peak
memory (getrusage of the child). Every run must
end with exit 0, 2 or 3 within 5 s; the exit status is 1 when one does not.

Usage: bench/absurd_scenes.py NHC [--count 200] [--seed 44] [--limit 5] [--jobs 1] [--markdown FILE]
"""
import argparse
import concurrent.futures
import os
import random
import subprocess
import sys
import tempfile
import threading
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
    """cmd's exit code ("timeout" when killed at 12 x limit, a hang detector), wall and processor seconds, peak
    resident set (KB) and last line of standard error, from the child's own rusage (wait4), so
    that runs may go side by side."""
    start = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    killed = []
    timer = threading.Timer(limit * 12, lambda: (killed.append(True), p.kill()))
    timer.start()
    err = p.stderr.read().decode(errors="replace").strip().splitlines()
    p.stderr.close()
    _, status, usage = os.wait4(p.pid, 0)
    timer.cancel()
    p.returncode = os.waitstatus_to_exitcode(status)
    elapsed = time.monotonic() - start
    code = "timeout" if killed else p.returncode
    return code, elapsed, usage.ru_utime + usage.ru_stime, usage.ru_maxrss, err[-1] if err else ""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("nhc")
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--seed", type=int, default=44)
    ap.add_argument("--limit", type=float, default=5.0)
    ap.add_argument("--markdown")
    ap.add_argument("--jobs", type=int, default=1, help="runs side by side (each measured on its own)")
    args = ap.parse_args()
    rng = random.Random(args.seed)
    commands = {"derive": ["derive"], "derive --format latex": ["derive", "--format", "latex"],
                "generate": ["generate", "-q"]}
    stats = {name: {"codes": {}, "worst": (0.0, ""), "cpu": 0.0, "rss": 0, "bad": []} for name in commands}
    with tempfile.TemporaryDirectory() as tmp:
        tasks = []
        for i in range(args.count):
            if i % 10 == 9:
                lagr, extra = squared_definitions(rng.randint(20, 96))
            else:
                lagr, extra = lagrangian(rng), ""
            path = os.path.join(tmp, f"absurd_{i:03d}.toml")
            with open(path, "w") as f:
                f.write(scene_text(lagr, extra))
            out = os.path.join(tmp, f"out_{i:03d}")
            for name, sub in commands.items():
                tasks.append((i, lagr, name, [args.nhc] + sub + [path] + (["-o", out] if sub[0] == "generate" else [])))
        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
            futures = {pool.submit(run, task[3], args.limit): task for task in tasks}
            done = ((futures[f], f.result()) for f in concurrent.futures.as_completed(futures))
            for (i, lagr, name, _), (code, elapsed, cpu, rss, last) in done:
                s = stats[name]
                s["codes"][code] = s["codes"].get(code, 0) + 1
                if elapsed > s["worst"][0]:
                    s["worst"] = (elapsed, lagr)
                s["rss"] = max(s["rss"], rss)
                s["cpu"] = max(s["cpu"], cpu)
                print(f"run {name} #{i}: exit {code} in {elapsed:.2f} s ({cpu:.2f} s processor), "
                      f"peak {rss / 1024:.0f} MB", flush=True)
                if code not in (0, 2, 3) or elapsed > args.limit:
                    s["bad"].append((i, code, elapsed, lagr, last))
                    print(f"FAIL {name} #{i}: exit {code} in {elapsed:.2f} s: {lagr}: {last}", file=sys.stderr)
    sys.stdout.flush()
    rows = ["| command | scenes | exit codes | worst wall time (s) | worst processor time (s) | "
            "worst peak memory (MB) | over the limit (wall) |",
            "|---|---|---|---|---|---|---|"]
    for name, s in stats.items():
        codes = ", ".join(f"{k}: {v}" for k, v in sorted(s["codes"].items(), key=lambda kv: str(kv[0])))
        rows.append(f"| `nhc {name}` | {args.count} | {codes} | {s['worst'][0]:.2f} | {s['cpu']:.2f} | "
                    f"{s['rss'] / 1024:.0f} | "
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
