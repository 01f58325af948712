#!/usr/bin/env python3
"""Throughput of `nhc ensemble` on the knife-edge chain N = 4 (bench/knife_chain.py): runs per
second on 1 and 2 MPI ranks (and 1 and 2 threads of one process), and the overhead per run —
scheduling, collecting the records, checkpoints and writing FILE.h5 — against a run's
integration time. Writes bench/ensemble.md; every number in it is measured by this script.

Overhead per run = (wall time of the run phase x workers - sum of the runs' own times) / runs,
the time a worker is not integrating, as `nhc ensemble` prints it. Each configuration is run
REPEATS times; the table shows the run with the median throughput.

Usage: bench/ensemble.py [NHC] [MPIEXEC]   (defaults: build/cli/nhc, mpirun)
Environment: NHC_ENSEMBLE_GRID (default "40 50": k and alpha values, 2000 runs), REPEATS (3).
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import knife_chain  # noqa: E402

SUMMARY = re.compile(r"on (\d+) ranks? x (\d+) threads?; build \S+ s, runs (\S+) s \((\S+) runs/s; per run: "
                     r"integration (\S+) ms, overhead (\S+) ms = (\S+) %\)")


def load_average():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def run(command, env):
    out = subprocess.run(command, env=env, check=True, capture_output=True, text=True).stdout
    m = SUMMARY.search(out)
    if not m:
        raise RuntimeError("no summary in the output of %s:\n%s" % (" ".join(command), out))
    ranks, threads, wall, rate, integration, overhead, percent = m.groups()
    return {"ranks": int(ranks), "threads": int(threads), "wall": float(wall), "rate": float(rate),
            "integration": float(integration), "overhead": float(overhead), "percent": float(percent)}


def main(argv):
    root = os.path.dirname(HERE)
    nhc = os.path.abspath(argv[1] if len(argv) > 1 else os.path.join(root, "build", "cli", "nhc"))
    mpiexec = argv[2] if len(argv) > 2 else shutil.which("mpirun") or "mpirun"
    nk, na = (int(x) for x in os.environ.get("NHC_ENSEMBLE_GRID", "40 50").split())
    repeats = int(os.environ.get("REPEATS", "3"))
    work = tempfile.mkdtemp(prefix="nhc-ensemble-bench-")
    env = dict(os.environ, NHC_CACHE_DIR=os.path.join(work, "cache"),
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    knife_chain.main(["knife_chain.py", work, "4"])
    scene = os.path.join(work, "knife_chain_4.toml")
    design = ["--vary", "k=5:20:%d" % nk, "--vary", "alpha=0.1:0.5:%d" % na]
    out = os.path.join(work, "out.h5")
    ensemble = [nhc, "ensemble", scene] + design + ["-o", out]
    subprocess.run(ensemble + ["--threads", "1"], env=env, check=True, capture_output=True)  # compile once

    configurations = [
        ("mpirun -np 1", [mpiexec, "--oversubscribe", "-np", "1"] + ensemble),
        ("mpirun -np 2", [mpiexec, "--oversubscribe", "-np", "2"] + ensemble),
        ("one process, --threads 1", ensemble + ["--threads", "1"]),
        ("one process, --threads 2", ensemble + ["--threads", "2"]),
    ]
    load_before = load_average()
    rows = []
    for name, command in configurations:
        results = sorted((run(command, env) for _ in range(repeats)), key=lambda r: r["rate"])
        rows.append((name, results[len(results) // 2], [r["percent"] for r in results]))
        sys.stderr.write("bench: %s: %s\n" % (name, rows[-1][1]))
    load_after = load_average()
    shutil.rmtree(work)

    lines = [
        "# nhc ensemble: throughput and overhead (bench/ensemble.py)",
        "",
        "Knife-edge chain N = 4 (bench/knife_chain.py: 12 coordinates, 4 constraints, chetaev, t from 0 to %g, "
        "rtol %g), a %d x %d grid of the spring constant k and the slope alpha: %d runs per ensemble, final "
        "states kept (`--keep final`, 100 output intervals for the drift). Measured %s on %d cores; load average "
        "%s before, %s after (the machine is shared: wall times include waiting for a core)."
        % (knife_chain.T_END, knife_chain.RTOL, nk, na, nk * na, time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
           os.cpu_count(), load_before, load_after),
        "",
        "    " + " ".join(["nhc", "ensemble", "knife_chain_4.toml"] + design + ["-o", "out.h5"]),
        "",
        "| configuration | runs/s | wall [s] | integration per run [ms] | overhead per run [ms] | overhead | "
        "overhead of the %d repeats |" % repeats,
        "|---|---|---|---|---|---|---|",
    ]
    for name, r, percents in rows:
        lines.append("| %s | %.1f | %.3f | %.3f | %.4f | %.2f %% | %s |" % (
            name, r["rate"], r["wall"], r["integration"], r["overhead"], r["percent"],
            ", ".join("%.2f %%" % p for p in percents)))
    lines += [
        "",
        "Overhead per run = (wall time of the run phase x workers - the runs' own times) / runs: scheduling "
        "(rank 0 hands out guided chunks, MPI_Send/MPI_Recv), collecting the records, checkpoints and the final "
        "HDF5 write, and the tail where one worker finishes before the other. The target is below "
        "5 % of a run's integration time. Not in the run phase: starting the processes (mpirun) and building "
        "the model (derivation and the compile cache's shared object), once per ensemble.",
        "",
    ]
    with open(os.path.join(HERE, "ensemble.md"), "w") as f:
        f.write("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
