#!/usr/bin/env python3
"""The animation page survives any fragment: malformed percent-encoding (#t=50%,
#t=%E0%A4%A) and unknown keys are ignored, never thrown; a valid #t= still opens the page paused at
that time. The page is a pendulum started at t0 = 1e6 (where 9-digit times were a staircase), loaded
in headless Chromium (browser_test.py's way); it must write its state (#nhc-state) with no error.
Exits 77 (skipped) where Chromium is missing.

    fragment_test.py --nhc build/cli/nhc --scene tests/cli/scenes/visual_pendulum.toml --out DIR
"""
import argparse
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from browser_test import SKIP, chromium, open_browser, page_state  # noqa: E402

T0 = 1e6


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nhc", required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    browser = chromium()
    if browser is None:
        print("skipped: Chromium is not installed (Debian: apt-get install chromium)")
        return SKIP
    out = pathlib.Path(args.out)
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    text = pathlib.Path(args.scene).read_text()
    text = text.replace("[initial]\n", f"[initial]\nt0 = {T0!r}\n", 1)
    text = re.sub(r"t_end = [0-9.]+", f"t_end = {T0 + 3.0!r}", text)
    scene = out / "pendulum_late.toml"
    scene.write_text(text)
    subprocess.run([args.nhc, "animate", str(scene), "--outputs", "300", "--rtol", "1e-8", "--atol", "1e-10", "-o", str(out / "page")], check=True,
                   stdout=subprocess.DEVNULL)
    page = (out / "page" / "index.html").resolve().as_uri()
    failures = []
    # (fragment, the time the page must show: None for "playing, any time")
    cases = [("#t=50%", None), ("#t=%E0%A4%A", None), ("#%ZZ=1&t=%", None), ("#marker=%&size=800x600", None),
             ("#t=%E0%A4%A&probe", None), (f"#t={T0 + 1.23!r}", T0 + 1.23), (f"#t={T0 + 1.24!r}", T0 + 1.24)]
    with tempfile.TemporaryDirectory() as profile, open_browser(browser, profile) as session:
        for fragment, shown in cases:
            tab = session.load(page + fragment)
            dom, console = tab.dom, tab.console
            tab.close()
            try:
                state = page_state(dom)
            except (AssertionError, ValueError) as e:  # no state, or not JSON: the page did not run
                failures.append(f"{fragment}: {e}")
                continue
            errors = state["errors"] + [c for c in console if "Uncaught" in c or "URIError" in c]
            if errors:
                failures.append(f"{fragment}: errors in the page: {errors}")
            if shown is not None and abs(state["t"] - shown) > 1e-9 * shown:
                failures.append(f"{fragment}: the page shows t = {state['t']!r}")
            print(f"{fragment}: t = {state['t']!r}, {len(errors)} errors")
    for failure in failures:
        print(f"FAIL: {failure}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
