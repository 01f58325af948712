#!/usr/bin/python3
"""Rewrites every string an nhc ensemble file holds (the scene, model and scene-file attributes,
the design's variable names, the state and invariant names) into text that would run
`touch MARKER` if anything handed it to a shell or to gnuplot as code: backquotes, $(...), a
newline, quotes, a gnuplot macro and a trailing backslash.
Usage: hostile_h5.py IN.h5 OUT.h5 MARKER"""
import shutil
import sys

import h5py
import numpy as np

source, target, marker = sys.argv[1:4]
shutil.copyfile(source, target)


def hostile(name):
    return (f"{name}`touch {marker}`$(touch {marker});\"'\n"
            f"@{name} set output '{marker}'\\").encode()


with h5py.File(target, "r+") as f:
    for key in ("scene", "model", "scene_file"):
        f.attrs[key] = np.bytes_(hostile(f.attrs[key].decode()))
    for path in ("design/names", "runs/state_names", "runs/invariant_names"):
        names = [hostile(n.decode()) for n in f[path][()]]
        del f[path]
        f[path] = np.array(names, dtype=h5py.string_dtype("ascii", max(len(n) for n in names)))
