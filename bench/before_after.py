#!/usr/bin/env python3
"""Two builds of nhc side by side on the real scenes (goal: the work budget must not slow
them): every example, the Whipple bicycle (also with --expand) and the knife chain of
bench/knife_chain.py, under `nhc derive` and `nhc generate`, each run `--repeat` times alternating
the two builds, best processor time (user + system of the child, getrusage) of each. Processor
time, not wall time, so that a loaded machine changes the verdict little.

Usage: bench/before_after.py BEFORE_NHC AFTER_NHC [--repeat 3] [--chain 1024] [--markdown FILE]
"""
import argparse
import glob
import os
import resource
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def cpu_seconds(cmd, env):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    used = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return p.returncode, used


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--chain", type=int, default=1024)
    ap.add_argument("--markdown")
    args = ap.parse_args()
    env = dict(os.environ, NHC_SCENE_CACHE="off")
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([sys.executable, os.path.join(ROOT, "bench", "knife_chain.py"), tmp, str(args.chain)],
                       check=True, stdout=subprocess.DEVNULL)
        scenes = sorted(glob.glob(os.path.join(ROOT, "examples", "*.toml")))
        scenes.append(os.path.join(ROOT, "examples", "whipple", "whipple_bicycle.toml"))
        chain = os.path.join(tmp, f"knife_chain_{args.chain}.toml")
        cases = [(os.path.basename(s), ["derive", s]) for s in scenes]
        cases.append(("whipple_bicycle.toml --expand", ["derive", "--expand", scenes[-1]]))
        cases.append((os.path.basename(chain), ["derive", chain]))
        cases += [(os.path.basename(s) + " (generate)", ["generate", "-q", "-o", tmp, s])
                  for s in (scenes[-1], chain)]
        rows = ["| scene | command | before (s) | after (s) | after / before | exits |", "|---|---|---|---|---|---|"]
        total = {"before": 0.0, "after": 0.0}
        for name, sub in cases:
            best = {"before": float("inf"), "after": float("inf")}
            codes = set()
            for _ in range(args.repeat):
                for which in ("before", "after"):
                    code, used = cpu_seconds([getattr(args, which)] + sub, env)
                    codes.add(code)
                    best[which] = min(best[which], used)
            for which in best:
                total[which] += best[which]
            ratio = best["after"] / best["before"] if best["before"] > 0 else float("nan")
            rows.append(f"| {name} | `nhc {sub[0]}` | {best['before']:.3f} | {best['after']:.3f} | {ratio:.2f} | "
                        f"{', '.join(map(str, sorted(codes)))} |")
            print(rows[-1], flush=True)
        rows.append(f"| all | | {total['before']:.3f} | {total['after']:.3f} | "
                    f"{total['after'] / total['before']:.2f} | |")
    table = "\n".join(rows)
    print(table)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(table + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
