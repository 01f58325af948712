#!/usr/bin/env python3
"""nhc generate writes the header nhc simulate builds for the same scene, byte for byte. simulate
derives the initial-point check before the header in one process, generate derives the header
alone, so this holds only if the printed form depends on the scene and not on what was derived
before (docs/architecture.md, the scene cache). The header simulate built is read from its scene
cache entry (jit/scene_cache.hpp: the record's `text` field, with `file_name` and `jacobian`),
in a cache directory of its own, and compared with `nhc generate --jacobian <that kind>`.

    generate_equals_simulate_test.py NHC SOURCE_DIR OUT_DIR
"""
import os
import pathlib
import shutil
import subprocess
import sys

SCENES = [
    "examples/particle.toml",
    "examples/chaplygin_sleigh.toml",
    "examples/rolling_disk.toml",
    "examples/rattleback.toml",                  # a larger system
    "examples/wheeled_pendulum_move.toml",       # [inputs]
    "examples/constant_speed_definitions.toml",  # [definitions]
    "examples/tumbling_top_quaternion.toml",     # quat(), a holonomic constraint
]


def records(cache):
    """The records of the scene cache entries: magic, key, sha256 and bytes lines, then fields
    written as `NAME SIZE\\nVALUE\\n` (SceneCacheRecord::serialize)."""
    for path in sorted((cache / "scenes").glob("*.entry")):
        payload = path.read_bytes().split(b"\n", 4)[4]
        fields, pos = {}, 0
        while pos < len(payload):
            end = payload.index(b"\n", pos)
            name, size = payload[pos:end].rsplit(b" ", 1)
            fields[name.decode()] = payload[end + 1:end + 1 + int(size)]
            pos = end + 1 + int(size) + 1
        yield fields


def main():
    nhc, source, out = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
    shutil.rmtree(out, ignore_errors=True)
    failures = 0
    for scene in SCENES:
        name = pathlib.Path(scene).stem
        cache = out / name / "cache"
        env = dict(os.environ, NHC_CACHE_DIR=str(cache))
        env.pop("NHC_SCENE_CACHE", None)
        run = subprocess.run([nhc, "simulate", str(source / scene)], env=env, capture_output=True, text=True, timeout=600)
        if run.returncode != 0:
            print(f"FAIL: nhc simulate {scene}: exit {run.returncode}\n{run.stderr}")
            failures += 1
            continue
        headers = [r for r in records(cache) if "text" in r]
        if len(headers) != 1:
            print(f"FAIL: {scene}: {len(headers)} headers in the scene cache, not 1")
            failures += 1
            continue
        built = headers[0]
        generated_dir = out / name / "generated"
        gen = subprocess.run([nhc, "generate", str(source / scene), "--quiet", "--jacobian", built["jacobian"].decode(),
                              "-o", str(generated_dir)], env=dict(os.environ, NHC_CACHE_DIR=str(out / name / "other")),
                             capture_output=True, text=True, timeout=600)
        if gen.returncode != 0:
            print(f"FAIL: nhc generate {scene}: exit {gen.returncode}\n{gen.stderr}")
            failures += 1
            continue
        generated = (generated_dir / built["file_name"].decode()).read_bytes()
        same = generated == built["text"]
        print(f"{scene}: {built['file_name'].decode()} ({built['jacobian'].decode()} Jacobian), "
              f"{len(generated)} bytes generated, {len(built['text'])} built by simulate: {'identical' if same else 'DIFFERENT'}")
        if not same:
            a, b = generated.decode().splitlines(), built["text"].decode().splitlines()
            line = next((k for k in range(min(len(a), len(b))) if a[k] != b[k]), min(len(a), len(b)))
            print(f"  first difference at line {line + 1}:\n  generate: {a[line] if line < len(a) else '(end)'}\n"
                  f"  simulate: {b[line] if line < len(b) else '(end)'}")
            failures += 1
    if failures:
        print(f"{failures} scene(s) failed")
        return 1
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
