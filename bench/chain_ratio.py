#!/usr/bin/env python3
"""Generated against hand-written knife chain, per N (goal: integration <= 1.2x at every N).

Runs `nhc_bench knife_chain_N.toml --handwritten bench/knife_chain_handwritten.hpp` ROUNDS times
per N (the sizes interleaved round by round); each run alternates the two integrations (at least
20 pairs or 2 s, nhc_bench's interleave_integrations) and reports their minima, wall and processor
time. Prints per N the smallest of the rounds' minima and the ratios, and the per-call ratios.

Usage: bench/chain_ratio.py NHC_BENCH SCENE_DIR ROUNDS N...  (scenes from bench/knife_chain.py)
"""
import json
import os
import subprocess
import sys
import tempfile


def main():
    bench, scenes, rounds, ns = sys.argv[1], sys.argv[2], int(sys.argv[3]), [int(n) for n in sys.argv[4:]]
    here = os.path.dirname(os.path.abspath(__file__))
    results = {n: [] for n in ns}
    with tempfile.TemporaryDirectory() as work:
        for _ in range(rounds):
            for n in ns:
                done = subprocess.run(
                    [bench, os.path.join(scenes, f"knife_chain_{n}.toml"), "--out", os.path.join(work, "out"),
                     "--handwritten", os.path.join(here, "knife_chain_handwritten.hpp"),
                     "--define", f"NHC_BENCH_CHAIN_N={n}"],
                    check=True, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
                results[n].append(json.loads(done.stdout.strip().splitlines()[-1]))
    print("| N | integration wall: generated / hand-written | processor time: generated / hand-written "
          "| per round (wall ratios) | residual call | Jacobian call | pairs per round | operations after CSE: residual, residual + Jacobian (joint) |")
    print("|---|---|---|---|---|---|---|---|")
    for n in ns:
        rs = results[n]
        g = min(r["integrate_s"] for r in rs)
        h = min(r["handwritten_integrate_s"] for r in rs)
        gc = min(r["integrate_cpu_s"] for r in rs)
        hc = min(r["handwritten_integrate_cpu_s"] for r in rs)
        rounds_text = ", ".join(f"{r['integrate_s'] / r['handwritten_integrate_s']:.2f}" for r in rs)
        rc = min(r["residual_call_s"] for r in rs) / min(r["handwritten_residual_call_s"] for r in rs)
        jc = min(r["jacobian_call_s"] for r in rs) / min(r["handwritten_jacobian_call_s"] for r in rs)
        print(f"| {n} | {g * 1e3:.3g} ms / {h * 1e3:.3g} ms (**{g / h:.2f}×**) | {gc * 1e3:.3g} ms / {hc * 1e3:.3g} ms "
              f"({gc / hc:.2f}×) | {rounds_text} | {rc:.2f}× | {jc:.2f}× | {rs[0]['integrate_repetitions']} "
              f"| {rs[0]['ops_by_function'].get('residual', ['?', '?'])[1]}, {rs[0]['residual_jacobian_joint_ops_after_cse']} |",
              flush=True)


if __name__ == "__main__":
    main()
