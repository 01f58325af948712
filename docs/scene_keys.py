"""The keys of the scene language as the scene loader itself states them.

The loader checks each table's keys against its own list (`check_keys` in
codegen/nhc/scene/scene_loader.cpp, the visual shapes' table in scene_visual.cpp, the [optimize]
settings in optimize/nhc/optimize/settings.cpp) and, for an unknown key, names every key it
accepts. This script asks it: it writes one small scene per table with the key `zz_probe`, runs
`nhc derive` (or `nhc optimize`) on it and reads the list from the one-line error. So the lists
cannot drift from the loader.

  scene_keys.py page  --nhc NHC --out FILE   writes the generated page scene-keys.md
  scene_keys.py check --nhc NHC --docs DIR   fails (exit 1) naming every key docs/scenes.md does
                                             not mention ([visual]'s shapes: docs/animate.md, whose
                                             table of shapes scenes.md points to; [optimize]:
                                             docs/optimize.md)
Both do the check; the docs build runs `page`, the test docs:scene_keys runs `check`.
"""
import argparse
import pathlib
import re
import subprocess
import sys
import tempfile

HEAD = 'name = "probe"\ncoordinates = ["x"]\nlagrangian = "x\'^2/2"\n'
PROBE = "zz_probe"


def ask(nhc, body, command="derive"):
    """The loader's one-line error for a scene holding the probe key: its 'expected one of' list
    (or 'known:' list)."""
    with tempfile.TemporaryDirectory() as work:
        scene = pathlib.Path(work) / "probe.toml"
        scene.write_text(HEAD + body)
        done = subprocess.run([nhc, command, str(scene)], capture_output=True, text=True, timeout=60)
    found = re.search(r"\((?:expected one of|known): ([^)]*)\)", done.stderr)
    if done.returncode != 2 or not found:
        sys.exit(f"scene_keys.py: nhc {command} did not name the accepted keys for\n{body}\n"
                 f"(exit {done.returncode}): {done.stderr.strip()}")
    return [k.strip() for k in found.group(1).split(",")]


def loader_keys(nhc):
    """(table, keys, where the page documents them) in the order of the page."""
    tables = [("top level", ask(nhc, f"{PROBE} = 1\n"), "scenes.md"),
              ("[simulate]", ask(nhc, f"[simulate]\n{PROBE} = 1\n"), "scenes.md"),
              ("[invariants] and [outputs] entries written as tables",
               ask(nhc, f'[invariants]\ne = {{ expression = "x", {PROBE} = 1 }}\n'), "scenes.md"),
              ("[contacts.NAME]", ask(nhc, f"[contacts.c]\n{PROBE} = 1\n"), "scenes.md"),
              ("[controller]", ask(nhc, f"[controller]\n{PROBE} = 1\n"), "scenes.md")]
    shapes = ask(nhc, f'[visual]\ns = {{ shape = "{PROBE}" }}\n')
    for shape in shapes:
        tables.append((f'[visual] shape = "{shape}"',
                       ask(nhc, f'[visual]\ns = {{ shape = "{shape}", {PROBE} = 1 }}\n'), "animate.md"))
    tables.append(("[optimize]", ask(nhc, f"[optimize]\n{PROBE} = 1\n", "optimize"), "optimize.md"))
    models = ask(nhc, f'models = ["{PROBE}"]\n')
    return tables, shapes, models


def mentioned(key, text):
    """The page names the key as a key: `key`, key = …, [key], [table.key] or "key" (a TOML
    string of an example: a model or a shape)."""
    k = re.escape(key)
    return bool(re.search(rf"`[^`\n]*(?<![\w']){k}(?![\w'])[^`\n]*`", text)
                or re.search(rf'"{k}"', text)
                or re.search(rf"(?<![\w']){k}\s*=", text)
                or re.search(rf"\[(?:[\w.]+\.)?{k}\]", text))


def missing(tables, shapes, models, docs):
    pages = {}
    gaps = []
    for table, keys, page in tables:
        text = pages.setdefault(page, (docs / page).read_text(encoding="utf-8"))
        gaps += [f"{page}: {table}: {key}" for key in keys if not mentioned(key, text)]
    scenes = pages.setdefault("scenes.md", (docs / "scenes.md").read_text(encoding="utf-8"))
    animate = pages.setdefault("animate.md", (docs / "animate.md").read_text(encoding="utf-8"))
    gaps += [f"animate.md: [visual] shape {s}" for s in shapes if not mentioned(s, animate)]
    gaps += [f"scenes.md: model {m}" for m in models if not mentioned(m, scenes)]
    return gaps


def page(tables, shapes, models):
    lines = ["# Scene keys (generated)", "",
             "Every key the scene loader accepts, table by table, as the loader itself lists them: "
             "generated at every build of this site by docs/scene_keys.py, which hands `nhc` a scene "
             "with an unknown key in each table and reads the keys its error message names. What "
             "each key means is on the [scene reference](scenes.md) (for `[visual]`'s shapes on "
             "[animate](animate.md), for `[optimize]` on [optimize](optimize.md)); the build fails when "
             "a key is missing there.", "",
             "| table | keys |", "|---|---|"]
    for table, keys, _ in tables:
        lines.append(f"| {table} | {', '.join(f'`{k}`' for k in keys)} |")
    lines += ["", f"Shapes of `[visual]`: {', '.join(f'`{s}`' for s in shapes)}.", "",
              f"Models (`models = [...]`, `[simulate] model`, `[reference.<model>]`): "
              f"{', '.join(f'`{m}`' for m in models)}.", "",
              "The other tables are keyed by the scene's own names: `[parameters]`, `[definitions]`, "
              "`[inputs]`, `[invariants]` and `[outputs]` by the names they introduce; `[initial]` by "
              "`t0`, `fixed`, the coordinates and the multipliers `lambda1`…; `[forces]` and "
              "`[reference]` by the coordinates (and `[reference.<model>]` by a model's name); "
              "`[visual]` by the names of its shapes.", ""]
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("action", choices=["page", "check"])
    parser.add_argument("--nhc", required=True)
    parser.add_argument("--docs", type=pathlib.Path, default=pathlib.Path(__file__).parent)
    parser.add_argument("--out", type=pathlib.Path)
    args = parser.parse_args()
    tables, shapes, models = loader_keys(args.nhc)
    gaps = missing(tables, shapes, models, args.docs)
    if gaps:
        sys.exit("scene_keys.py: keys the loader accepts that the docs do not mention:\n  " + "\n  ".join(gaps))
    if args.action == "page":
        args.out.write_text(page(tables, shapes, models), encoding="utf-8")
    count = sum(len(keys) for _, keys, _ in tables)
    print(f"scene keys: {count} keys in {len(tables)} tables, {len(shapes)} shapes, {len(models)} models, all documented")


if __name__ == "__main__":
    main()
