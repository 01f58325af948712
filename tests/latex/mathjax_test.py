#!/usr/bin/env python3
"""The math-only LaTeX (`nhc derive --format latex-math`, Jupyter's _repr_latex_) rendered by
MathJax (Debian libjs-mathjax) in headless Chromium: every example's equations typeset with no
MathJax error box, no raw LaTeX left in the page (\\section, \\begin, \\frac) and every equation
named R_<coordinate> present. Exits 77 (skipped) without Chromium or MathJax.

    mathjax_test.py --nhc build/cli/nhc --out build/tests/latex/mathjax SCENE...
"""
import argparse
import html
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

SKIP = 77
MATHJAX = pathlib.Path("/usr/share/javascript/mathjax/MathJax.js")

PAGE = """<!DOCTYPE html>
<html><head><meta charset="utf-8">
<script type="text/x-mathjax-config">
MathJax.Hub.Config({{tex2jax: {{inlineMath: [], displayMath: [['$$','$$']], processEnvironments: true}},
  TeX: {{noErrors: {{disabled: true}}, noUndefined: {{disabled: true}}}}, messageStyle: "none"}});
MathJax.Hub.Register.MessageHook("TeX Jax - parse error", function (m) {{
  document.body.setAttribute("data-tex-error", String(m[1])); }});
MathJax.Hub.Register.MessageHook("Math Processing Error", function (m) {{
  document.body.setAttribute("data-tex-error", "processing: " + String(m[2] && m[2].message)); }});
MathJax.Hub.Queue(function () {{ document.body.setAttribute("data-typeset", "done"); }});
</script>
<script src="file://{mathjax}?config=TeX-AMS_CHTML"></script>
</head><body><div id="math">{math}</div></body></html>
"""


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    return None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nhc", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("scenes", nargs="+")
    args = parser.parse_args()
    browser = chromium()
    if not browser or not MATHJAX.exists():
        print("skipped: needs chromium and libjs-mathjax")
        return SKIP
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    # One page for all scenes (one browser start): a block per scene, checked block by block.
    blocks, names = [], {}
    for k, scene in enumerate(args.scenes):
        math = subprocess.run([args.nhc, "derive", scene, "--format", "latex-math", "--form", "reduced"], capture_output=True,
                              text=True, check=True).stdout
        names[k] = re.findall(r"^  (R_\{.*?\}) &=", math, re.M)
        blocks.append(f'<div class="scene" id="scene-{k}">{html.escape(math)}</div><hr id="end-{k}">')
    page = out / "equations.html"
    page.write_text(PAGE.format(mathjax=MATHJAX, math="\n".join(blocks)))
    with tempfile.TemporaryDirectory() as profile:
        run = subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                              "--disable-background-networking", "--disable-component-update",
                              "--allow-file-access-from-files", f"--user-data-dir={profile}",
                              "--virtual-time-budget=120000", "--dump-dom", page.as_uri()],
                             capture_output=True, text=True, timeout=600)
    dom = run.stdout
    (out / "equations.dom.html").write_text(dom)
    failures = []
    if 'data-typeset="done"' not in dom:
        failures.append("MathJax did not finish typesetting the page")
    error = re.search(r'data-tex-error="([^"]*)"', dom)
    if error:
        failures.append("TeX error: " + html.unescape(error.group(1)))
    for k, scene in enumerate(args.scenes):
        begin, end = dom.find(f'id="scene-{k}"'), dom.find(f'id="end-{k}"')
        if begin < 0 or end < begin:
            failures.append(f"{scene}: its block is missing from the page")
            continue
        body = dom[begin:end]
        problems = []
        if re.search(r'class="[^"]*(MathJax_Error|merror|mjx-merror)', body):
            problems.append("an error box")
        if "mjx-chtml" not in body and "MJXc-display" not in body and "MathJax_CHTML" not in body:
            problems.append("no typeset math")
        text = re.sub(r"<script.*?</script>", "", body, flags=re.S)
        text = re.sub(r"<[^>]+>", " ", text)
        for raw in ("\\section", "\\subsection", "\\begin{", "\\frac", "\\texttt"):
            if raw in text:
                problems.append(f"raw LaTeX left: {raw}")
        if not names[k]:
            problems.append("no equation named R_{...}")
        if problems:
            failures.append(f"{scene}: " + "; ".join(problems))
        else:
            print(f"{scene}: typeset, {len(names[k])} equations ({', '.join(names[k][:4])}...)")
    for failure in failures:
        print(failure, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
