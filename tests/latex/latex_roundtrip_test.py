#!/usr/bin/env python3
"""nhc's LaTeX read back by an independent parser: every row nhc prints as LaTeX (the scene's L and
constraints, every model's residuals and constraints, the multiplier-free form, the definitions)
is turned into MathML by pandoc (texmath) and evaluated by mathml_eval.py at random points; the
text form of the same row, read by SymPy, must give the same number. A printer that drops a
bracket (½·Jw·(…)² + (…)² for ½·Jw·((…)² + (…)²)) changes the number and fails.

    latex_roundtrip_test.py --nhc build/cli/nhc SCENE...          every row of every scene
    latex_roundtrip_test.py --trees-program build/tests/latex/nhc_latex_trees --count N --out DIR
                                                                  N random expression trees

nhc_latex_trees writes the trees' text forms one per line and their LaTeX as the documents print
an equation (align* rows, long ones broken between terms and factors); they are paired in order.
"""
import argparse
import pathlib
import random
import re
import shutil
import subprocess
import sys

import mpmath

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import mathml_eval  # noqa: E402

mpmath.mp.dps = 30
POINTS = 3


def latex_rows(math):
    """(lhs, rhs) of every equation row of `--format latex-math`, continuation rows joined."""
    rows = []
    for line in re.split(r" \\\\\n|\n", math):
        line = line.strip()
        if not line or line.startswith("\\begin{align") or line.startswith("\\end{align"):
            continue
        if line.startswith("&\\text{") or line.startswith("&M_r\\,"):
            continue
        if line.startswith("&\\quad "):
            lhs, rhs = rows[-1]
            rows[-1] = (lhs, rhs + " " + line[len("&\\quad "):])
            continue
        lhs, sep, rhs = line.partition(" &= ")
        if not sep:
            raise SystemExit(f"unreadable LaTeX row: {line[:200]}")
        rows.append((lhs, rhs))
    out = []
    for lhs, rhs in rows:
        rhs = rhs.strip()
        for suffix in (" = 0 \\quad\\text{(monitored)}", " = 0"):
            if rhs.endswith(suffix):
                rhs = rhs[: -len(suffix)]
                break
        out.append((lhs, rhs.strip()))
    return out


def text_rows(text):
    """(name, expression) of every equation line of `--format text`."""
    out = []
    for line in text.splitlines():
        if not line.startswith("  ") or line.startswith("  not applicable") or \
                line.startswith("  multiplier-free form"):
            continue
        name, sep, expression = line.strip().partition(" = ")
        if not sep:
            raise SystemExit(f"unreadable text row: {line[:200]}")
        if expression.endswith(" = 0"):
            expression = expression[:-4]
        out.append((name, expression))
    return out


def compare(label, pairs, rng):
    """pairs: (name, text expression, latex expression). Returns the failures."""
    failures = []
    trees = mathml_eval.to_mathml([latex for _, _, latex in pairs])
    for (name, text, latex), tree in zip(pairs, trees):
        try:
            reading = mathml_eval.compile_tree(tree)
        except mathml_eval.ReadError as e:
            failures.append(f"{label} {name}: ReadError: {e}\n    latex: {latex[:300]}")
            continue
        try:
            names, f = mathml_eval.text_function(text)
        except (SyntaxError, TypeError, ValueError) as e:
            failures.append(f"{label} {name}: SymPy cannot read the text form: {e}\n    text: {text[:300]}")
            continue
        for _ in range(POINTS):
            values = {n: mpmath.mpf(rng.uniform(0.3, 1.7)) for n in names}
            try:
                expected = f(values)
            except (TypeError, ValueError, ArithmeticError, AttributeError):
                continue  # outside the text form's domain at this point (atan2 of a complex number)
            try:
                got = reading(values)
            except (mathml_eval.ReadError, TypeError, ValueError, ArithmeticError, AttributeError) as e:
                failures.append(f"{label} {name}: {type(e).__name__}: {e}\n    latex: {latex[:300]}")
                break
            if not mathml_eval.close(expected, got, digits=12):
                failures.append(f"{label} {name}: text gives {mpmath.nstr(expected, 15)}, LaTeX gives "
                                f"{mpmath.nstr(got, 15)}\n    text:  {text[:300]}\n    latex: {latex[:300]}")
                break
    return failures


def scene_pairs(nhc, scene):
    def run(fmt):
        return subprocess.run([nhc, "derive", scene, "--format", fmt, "--form", "reduced"], capture_output=True,
                              text=True, check=True).stdout
    texts, latexes = text_rows(run("text")), latex_rows(run("latex-math"))
    if len(texts) != len(latexes):
        raise SystemExit(f"{scene}: {len(texts)} text rows but {len(latexes)} LaTeX rows")
    return [(name, text, latex) for (name, text), (_, latex) in zip(texts, latexes)]


def tree_pairs(program, count, seed, out):
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    text_file, tex_file = out / "trees.txt", out / "trees.tex"
    subprocess.run([program, str(count), str(seed), str(text_file), str(tex_file)], check=True)
    texts = text_file.read_text().splitlines()
    latexes = latex_rows(tex_file.read_text())
    if len(texts) != count or len(latexes) != count:
        raise SystemExit(f"{count} trees but {len(texts)} text rows and {len(latexes)} LaTeX rows")
    return [(f"tree {k + 1} ({lhs})", text, latex) for k, (text, (lhs, latex)) in enumerate(zip(texts, latexes))]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nhc")
    parser.add_argument("--trees-program")
    parser.add_argument("--count", type=int, default=3000)
    parser.add_argument("--out", default=".")
    parser.add_argument("--seed", type=int, default=20260529)
    parser.add_argument("scenes", nargs="*")
    args = parser.parse_args()
    rng = random.Random(args.seed)
    failures, rows = [], 0
    if shutil.which("pandoc") is None:
        print("skipped: needs pandoc")
        return 77
    if args.trees_program:
        pairs = tree_pairs(args.trees_program, args.count, args.seed, args.out)
        rows += len(pairs)
        failures += compare("", pairs, rng)
    for scene in args.scenes:
        pairs = scene_pairs(args.nhc, scene)
        rows += len(pairs)
        failures += compare(pathlib.Path(scene).name, pairs, rng)
    for f in failures:
        print(f)
    print(f"{rows} rows read back, {len(failures)} differ from the text form")
    return 1 if failures or rows == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
