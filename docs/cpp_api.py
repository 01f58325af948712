"""The C++ API reference of the runtime and the jit, written from their installed headers.

Every header of the runtime (runtime/nhc/runtime, base/nhc/runtime: installed as nhc/runtime/)
and of the jit (jit/nhc/jit.hpp, jit/nhc/jit/) becomes one section of the page cpp-api.md: the
header's \\brief as text, then its declarations with their /// comments as C++ — the header
itself without includes, namespace lines and private members. Run at every docs build
(docs/build_docs.cmake), so the page is the headers of the build.
usage: cpp_api.py --source SOURCE_DIR --out FILE
"""
import argparse
import pathlib
import re

GROUPS = [
    ("The runtime (`nhc::runtime`, target `nhc::runtime`)",
     "Integrates a generated model with SUNDIALS IDA: `#include \"nhc/runtime/runtime.hpp\"` "
     "([the runtime](runtime.md) explains it, [generated code](generated-code.md) the model's contract, "
     "[link generated code into an application](howto/application.md) shows it at work).",
     ["runtime/nhc/runtime/runtime.hpp", "runtime/nhc/runtime/*.hpp", "runtime/nhc/runtime/*.h",
      "base/nhc/base/*.hpp"]),
    ("The jit (`nhc::jit`, target `nhc::jit`)",
     "A scene's model derived, generated, compiled and loaded at run time, with its caches: "
     "`#include \"nhc/jit.hpp\"` ([library](library.md)).",
     ["jit/nhc/jit.hpp", "jit/nhc/jit/build.hpp", "jit/nhc/jit/*.hpp"]),
]


def headers(source, patterns):
    seen = []
    for pattern in patterns:
        for path in sorted(source.glob(pattern)):
            if path not in seen:
                seen.append(path)
    return seen


def split_header(text):
    """(brief, declarations): the \\file/\\brief block as prose, the rest as code without the
    lines a reader of the API does not need."""
    lines = text.splitlines()
    brief, body, i = [], [], 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("/// \\file"):
            i += 1
            while i < len(lines) and lines[i].startswith("///"):
                brief.append(lines[i][3:].strip().replace("\\brief ", ""))
                i += 1
            continue
        body.append(line)
        i += 1
    kept, private_indent = [], None
    for line in body:
        stripped = line.strip()
        indent = len(line) - len(line.lstrip())
        if private_indent is not None:
            # A private section ends at the class's closing brace or the next access label.
            if (stripped.startswith("};") and indent < private_indent) or stripped in ("public:", "protected:"):
                private_indent = None
                if stripped == "protected:":
                    private_indent = indent + 1
                    continue
            else:
                continue
        if stripped == "private:":
            private_indent = indent + 1
            continue
        if (stripped.startswith(("#pragma", "#include")) or re.match(r"^(namespace [\w:]+ \{|\}\s*// namespace)", stripped)
                or re.match(r"^#(ifndef|define|endif)\s+NHC_\w+_H\b", stripped)):
            continue
        kept.append(line)
    code = "\n".join(kept).strip("\n")
    code = re.sub(r"\n{3,}", "\n\n", code)
    code = re.sub(r"\n\n(\s*\};)", r"\n\1", code)  # no blank line left where a private section was
    return " ".join(b for b in brief if b), code


def page(source):
    out = ["# C++ API: runtime and jit", "",
           "Generated at every build of this site from the installed headers (docs/cpp_api.py): each "
           "header's summary, then its declarations with their comments, without includes and private "
           "members. The code generator's own API (`nhc::codegen`: scenes, derivation, analysis, "
           "emitters) is introduced on [library](library.md).", ""]
    for title, intro, patterns in GROUPS:
        out += [f"## {title}", "", intro, ""]
        for path in headers(source, patterns):
            include = "nhc/" + str(path.relative_to(source)).split("/nhc/", 1)[1]
            brief, code = split_header(path.read_text(encoding="utf-8"))
            out += [f"### `{include}`", ""]
            if brief:
                out += [brief, ""]
            if code:
                language = "c" if path.suffix == ".h" else "cpp"
                out += [f"```{language}", code, "```", ""]
    return "\n".join(out)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--source", type=pathlib.Path, required=True)
    parser.add_argument("--out", type=pathlib.Path, required=True)
    args = parser.parse_args()
    text = page(args.source)
    args.out.write_text(text, encoding="utf-8")
    print(f"C++ API page: {text.count('### ')} headers")


if __name__ == "__main__":
    main()
