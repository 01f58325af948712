#!/usr/bin/env python3
"""Scaling of nhc's symbolic front end, cold: the scene cache off, a fresh cache dir.

For each N of a scene family (bench/knife_chain.py, bench/particle_chain.py or the rigid bodies of
bench/rolling_balls.py) and one model:
wall seconds and peak resident memory (wait4's ru_maxrss) of the three commands
`nhc derive`, `nhc analyze` and `nhc generate`. Each command runs the pipeline up to its stage,
so the front end as a user sees it is `nhc generate` (derive + analyze + generate in one
process); the per-stage columns are the differences derive, analyze − derive, generate − analyze.
The generated header's operations after CSE (its banner's total) and its size are recorded too.
A command under 1 s is run 3 times (the shortest wall time, the largest peak memory).
Every command has a time limit: one that hits it is recorded as "timed out" and the larger N of
the family are not tried (recorded as "skipped"). A failing command is recorded with its error.

--simulate-up-to N: additionally a cold `nhc simulate` (scene cache off, a fresh compile cache: derive,
compile, integrate) at every N up to N: wall seconds, peak memory.

--warm N: additionally `nhc simulate` twice at N with the scene cache on (a fresh cache dir):
the first run fills the caches, the second is the warm run; its derive/compile/integrate come
from simulate's own "time:" line, the wall time from here.

Writes one JSON object (bench/report.py turns it into tables); prints progress to stderr.

Usage: frontend_scaling.py NHC OUT.json [--family knife_chain|particle_chain|rolling_balls] [--model M]
                           [--timeout S] [--warm N] [--warm-timeout S] [--simulate-up-to N] N [N ...]
Everything in the JSON is measured in this run.
"""
import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import knife_chain  # noqa: E402
import particle_chain  # noqa: E402
import rolling_balls  # noqa: E402

FAMILIES = {"knife_chain": knife_chain, "particle_chain": particle_chain, "rolling_balls": rolling_balls}
TOTAL_LINE = re.compile(r"^//   total\s+(\d+)\s+(\d+)$", re.M)


def header_size(directory, scene_name, model):
    """(operations after CSE, bytes) of the header `nhc generate` wrote, or (None, None)."""
    path = os.path.join(directory, "%s_%s.hpp" % (scene_name, model))
    try:
        with open(path) as f:
            text = f.read()
    except OSError:
        return None, None
    m = TOTAL_LINE.search(text)
    return (int(m.group(2)) if m else None), len(text.encode())


def run_limited(args, timeout, env):
    """Runs args in its own process group; returns (status, seconds, peak MB, stdout+stderr tail).
    status: "ok", "timed out" (the group killed at the limit) or "failed (exit K)"."""
    start = time.perf_counter()
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env,
                            start_new_session=True)
    killed = threading.Event()

    def kill():
        killed.set()
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    timer = threading.Timer(timeout, kill)
    timer.start()
    chunks = []
    reader = threading.Thread(target=lambda: chunks.append(proc.stdout.read()))
    reader.start()
    _, wstatus, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - start
    timer.cancel()
    reader.join()
    proc.returncode = os.waitstatus_to_exitcode(wstatus)
    out = b"".join(chunks).decode(errors="replace")
    peak_mb = usage.ru_maxrss / 1024.0
    if killed.is_set():
        return "timed out", seconds, peak_mb, out
    if proc.returncode != 0:
        return "failed (exit %d)" % proc.returncode, seconds, peak_mb, out
    return "ok", seconds, peak_mb, out


def error_line(out):
    lines = [line for line in out.strip().splitlines() if line.strip()]
    return lines[-1][:300] if lines else ""


def measure_front_end(nhc, family, model, ns, timeout, tmp, simulate_up_to=0):
    env = dict(os.environ, NHC_SCENE_CACHE="off", NHC_CACHE_DIR=os.path.join(tmp, "cold-cache"))
    rows, stop = [], None
    for n in ns:
        if stop:
            rows.append({"n": n, "status": "skipped (%s)" % stop})
            continue
        scene = os.path.join(tmp, "%s_%d.toml" % (family.__name__, n))
        with open(scene, "w") as f:
            f.write(family.scene_text(n))
        row = {"n": n, "commands": {}}
        headers = os.path.join(tmp, "headers_%d" % n)
        for cmd in ("derive", "analyze", "generate"):
            args = [nhc, cmd, "--model", model]
            if cmd == "generate":
                args += ["-q", "-o", headers]
            status, sec, peak, out = run_limited(args + [scene], timeout, env)
            # Short commands are dominated by noise (process start, a loaded machine): best of 3.
            for _ in range(2 if status == "ok" and sec < 1.0 else 0):
                again = run_limited(args + [scene], timeout, env)
                if again[0] == "ok":
                    sec, peak = min(sec, again[1]), max(peak, again[2])
            entry = {"status": status, "s": sec, "peak_mb": peak}
            if status != "ok":
                entry["error"] = "timed out after %g s" % timeout if status == "timed out" else error_line(out)
            row["commands"][cmd] = entry
            print("%s %s N=%d: %s %s %.2f s, %.0f MB" % (family.__name__, model, n, cmd, status, sec, peak),
                  file=sys.stderr, flush=True)
            if status != "ok":
                break
        c = row["commands"]
        if all(c.get(k, {}).get("status") == "ok" for k in ("derive", "analyze", "generate")):
            row["status"] = "ok"
            row["derive_s"] = c["derive"]["s"]
            row["analyze_s"] = max(0.0, c["analyze"]["s"] - c["derive"]["s"])
            row["generate_s"] = max(0.0, c["generate"]["s"] - c["analyze"]["s"])
            row["front_end_s"] = c["generate"]["s"]
            row["peak_mb"] = max(e["peak_mb"] for e in c.values())
            row["ops_after_cse"], row["header_bytes"] = header_size(headers, "%s_%d" % (family.__name__, n), model)
            if n <= simulate_up_to:
                row["simulate"] = cold_simulate(nhc, scene, model, n, timeout, tmp)
        else:
            bad = next(k for k in ("derive", "analyze", "generate") if c.get(k, {}).get("status") != "ok")
            row["status"] = "%s: %s" % (bad, c[bad]["status"])
            row["error"] = c[bad].get("error", "")
            if c[bad]["status"] == "timed out":
                stop = "nhc %s timed out at N = %d" % (bad, n)
        rows.append(row)
    return rows


def slope(rows, n_min, n_max):
    """Least-squares slope of log(front end seconds) against log N over n_min <= N <= n_max."""
    pts = [(math.log(r["n"]), math.log(r["front_end_s"])) for r in rows
           if r.get("status") == "ok" and n_min <= r["n"] <= n_max and r["front_end_s"] > 0]
    if len(pts) < 2:
        return None, [r["n"] for r in rows if r.get("status") == "ok" and n_min <= r["n"] <= n_max]
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    sxy = sum((p[0] - mx) * (p[1] - my) for p in pts)
    return (sxy / sxx if sxx else None), [r["n"] for r in rows
                                          if r.get("status") == "ok" and n_min <= r["n"] <= n_max]


def cold_simulate(nhc, scene, model, n, timeout, tmp):
    """`nhc simulate` with nothing cached: derive, compile and integrate the scene's own run."""
    env = dict(os.environ, NHC_SCENE_CACHE="off", NHC_CACHE_DIR=os.path.join(tmp, "simulate-cache-%d" % n))
    status, sec, peak, out = run_limited([nhc, "simulate", scene, "--model", model, "--backend", "compiled", "-o",
                                          os.path.join(tmp, "simulate_%d.csv" % n)], timeout, env)
    entry = {"status": status, "wall_s": sec, "peak_mb": peak}
    if status != "ok":
        entry["error"] = "timed out after %g s" % timeout if status == "timed out" else error_line(out)
    print("cold simulate N=%d: %s %.2f s, %.0f MB" % (n, status, sec, peak), file=sys.stderr, flush=True)
    return entry


TIME_LINE = re.compile(r"time: derive ([0-9.eE+-]+) s( \(scene cache\))?, compile ([0-9.eE+-]+) s( \(cached\))?, "
                       r"integrate ([0-9.eE+-]+) s")


def measure_warm(nhc, family, model, n, timeout, tmp):
    """`nhc simulate` at N twice with the scene cache on; the second run is the warm one."""
    env = dict(os.environ, NHC_CACHE_DIR=os.path.join(tmp, "warm-cache"))
    env.pop("NHC_SCENE_CACHE", None)
    scene = os.path.join(tmp, "warm_%s_%d.toml" % (family.__name__, n))
    with open(scene, "w") as f:
        f.write(family.scene_text(n))
    result = {"n": n, "model": model}
    for run in ("cold", "warm"):
        args = [nhc, "simulate", scene, "--model", model, "--backend", "compiled", "-o", os.path.join(tmp, "warm.csv")]
        status, sec, peak, out = run_limited(args, timeout, env)
        entry = {"status": status, "wall_s": sec, "peak_mb": peak}
        m = TIME_LINE.search(out)
        if status == "ok" and m:
            entry.update(derive_s=float(m.group(1)), scene_cache=bool(m.group(2)), compile_s=float(m.group(3)),
                         compile_cached=bool(m.group(4)), integrate_s=float(m.group(5)))
        elif status == "ok":
            entry["status"] = "failed (no time line in simulate's output)"
        else:
            entry["error"] = "timed out after %g s" % timeout if status == "timed out" else error_line(out)
        result[run] = entry
        print("warm simulate N=%d, %s run: %s %.2f s" % (n, run, entry["status"], sec), file=sys.stderr, flush=True)
        if entry["status"] != "ok":
            break
    return result


def main():
    argv = sys.argv[1:]
    opts = {"--family": "knife_chain", "--model": "chetaev", "--timeout": "600", "--warm": None,
            "--warm-timeout": "900", "--simulate-up-to": "0"}
    rest = []
    i = 0
    while i < len(argv):
        if argv[i] in opts and i + 1 < len(argv):
            opts[argv[i]] = argv[i + 1]
            i += 2
        else:
            rest.append(argv[i])
            i += 1
    if len(rest) < 3 or opts["--family"] not in FAMILIES:
        raise SystemExit(__doc__)
    nhc, out = rest[0], rest[1]
    ns = sorted(int(a) for a in rest[2:])
    family = FAMILIES[opts["--family"]]
    timeout = float(opts["--timeout"])
    with tempfile.TemporaryDirectory(prefix="nhc-frontend-") as tmp:
        rows = measure_front_end(nhc, family, opts["--model"], ns, timeout, tmp, int(opts["--simulate-up-to"]))
        warm = None
        if opts["--warm"]:
            warm = measure_warm(nhc, family, opts["--model"], int(opts["--warm"]),
                                float(opts["--warm-timeout"]), tmp)
    fit, fit_ns = slope(rows, 64, 1024)
    fit_all, fit_all_ns = slope(rows, 1, 1 << 30)
    result = {"family": opts["--family"], "model": opts["--model"], "timeout_s": timeout, "rows": rows,
              "slope_64_1024": fit, "slope_64_1024_ns": fit_ns, "slope_all": fit_all, "slope_all_ns": fit_all_ns}
    if warm:
        result["warm_simulate"] = warm
    with open(out + ".tmp", "w") as f:
        json.dump(result, f, indent=1)
    os.replace(out + ".tmp", out)


if __name__ == "__main__":
    main()
