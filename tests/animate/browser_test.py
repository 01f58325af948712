#!/usr/bin/env python3
"""`nhc animate` in a real browser: the page of one example is loaded in headless
Chromium at two times through its fragment (#t=…&marker=…&size=…), each load giving the page's
state (its camera and errors, #nhc-state) and then a screenshot of the same page. One browser
serves both loads (headless.py: a fresh tab each). Fails on an error in the page or on
the console, a blank picture, two times giving the same picture, or a marker that is not where
the CSV of `nhc simulate` (an independent run of the same scene) puts the shape's point after the
page's camera projection. Exits 77 (skipped) where Chromium is missing.

    browser_test.py --nhc build/cli/nhc --scene examples/rolling_ball.toml --marker ball \
                    --expect x,y,0.5 --out build/animate-test/rolling_ball
"""
import argparse
import csv
import json
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from headless import Browser  # noqa: E402

WIDTH, HEIGHT = 800, 600
SKIP = 77


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def open_browser(browser, profile):
    """One headless Chromium for all the page loads of a test (WebGL in software: SwiftShader)."""
    return Browser(browser, profile, WIDTH, HEIGHT, ["--use-angle=swiftshader", "--enable-unsafe-swiftshader"])


def errors_in(console):
    """The console lines that report an error (an uncaught exception, console.error, a failed load)."""
    return [c for c in console if "Uncaught" in c or "rror" in c]


def page_state(dom):
    match = re.search(r'<pre id="nhc-state"[^>]*>(.*?)</pre>', dom, re.S)
    if not match:
        raise AssertionError("the page wrote no state (#nhc-state): it did not run")
    return json.loads(match.group(1).replace("&quot;", '"').replace("&amp;", "&"))


def project(state, point):
    """Pixel of a scene point under the page's camera (three.js: column-major 4x4 matrices)."""
    view = np.array(state["view"]).reshape(4, 4).T
    projection = np.array(state["projection"]).reshape(4, 4).T
    clip = projection @ view @ np.array([*point, 1.0])
    ndc = clip[:3] / clip[3]
    return np.array([(ndc[0] + 1) / 2 * state["width"], (1 - ndc[1]) / 2 * state["height"]])


def marker_pixel(image):
    """Centre of the magenta marker (#ff00ff) in the screenshot, or None."""
    rgb = np.asarray(image.convert("RGB")).astype(int)
    mask = (rgb[:, :, 0] > 220) & (rgb[:, :, 1] < 60) & (rgb[:, :, 2] > 220)
    if mask.sum() < 4:
        return None
    rows, cols = np.nonzero(mask)
    return np.array([cols.mean() + 0.5, rows.mean() + 0.5])


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nhc", required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--marker", required=True, help="the visual whose point is checked")
    parser.add_argument("--expect", required=True,
                        help="its point from the CSV: three entries, each a column name or a number (x,y,0.5)")
    parser.add_argument("--out", required=True, help="directory for the page, the CSV and the screenshots")
    parser.add_argument("--rows", default="30,70", help="the two CSV rows (of 100 intervals) to look at")
    args = parser.parse_args()
    browser = chromium()
    if browser is None:
        print("skipped: Chromium is not installed (Debian: apt-get install chromium)")
        return SKIP
    out = pathlib.Path(args.out)
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    name = pathlib.Path(args.scene).stem
    flags = ["--outputs", "100"]
    subprocess.run([args.nhc, "simulate", args.scene, *flags, "-o", str(out / "run.csv")], check=True,
                   stdout=subprocess.DEVNULL)
    subprocess.run([args.nhc, "animate", args.scene, *flags, "-o", str(out / "page")], check=True,
                   stdout=subprocess.DEVNULL)
    with open(out / "run.csv") as f:
        rows = list(csv.DictReader(f))
    failures = []
    pictures = []
    with tempfile.TemporaryDirectory() as profile, open_browser(browser, profile) as session:
        for row_index in (int(r) for r in args.rows.split(",")):
            row = rows[row_index]
            t = float(row["t"])
            expected = [float(row[e]) if e in row else float(e) for e in args.expect.split(",")]
            url = (pathlib.Path(out / "page" / "index.html").resolve().as_uri() +
                   f"#t={t!r}&marker={args.marker}&size={WIDTH}x{HEIGHT}")
            page = session.load(url)
            state = page_state(page.dom)
            shot = out / f"{name}-t{t:g}.png"
            page.screenshot(shot)
            console = page.console
            page.close()
            errors = state["errors"] + errors_in(console)
            if errors:
                failures.append(f"t = {t}: errors in the page: {errors}")
            if abs(state["t"] - t) > 1e-9 * max(1.0, abs(t)):
                failures.append(f"t = {t}: the page shows t = {state['t']}")
            image = Image.open(shot)
            if image.size != (WIDTH, HEIGHT):
                failures.append(f"t = {t}: the screenshot is {image.size}, not {WIDTH}x{HEIGHT}")
            pixels = np.asarray(image.convert("RGB"))
            view = pixels[:int(0.85 * HEIGHT)]  # above the control bar
            colours = len(np.unique(view.reshape(-1, 3), axis=0))
            if view.std() < 5 or colours < 50:
                failures.append(f"t = {t}: the picture is blank ({colours} colours, spread {view.std():.1f})")
            pictures.append(pixels)
            expected_pixel = project(state, expected)
            found = marker_pixel(image)
            if found is None:
                failures.append(f"t = {t}: no marker in the picture (expected at {expected_pixel.round(1)})")
            else:
                distance = float(np.linalg.norm(found - expected_pixel))
                print(f"{name} t = {t}: marker {args.marker} at {found.round(1)}, the CSV's point projects to "
                      f"{expected_pixel.round(1)}: {distance:.2f} px")
                if distance > 3.0:
                    failures.append(f"t = {t}: the marker is {distance:.1f} px from the CSV's point")
    if len(pictures) == 2:
        differing = np.any(pictures[0] != pictures[1], axis=2).mean()
        print(f"{name}: {100 * differing:.2f} % of the pixels differ between the two times")
        if differing < 0.002:
            failures.append("the two times give the same picture")
    for failure in failures:
        print(f"FAIL {name}: {failure}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
