# Sphinx configuration of the nhc documentation site, built by `cmake --build build --target docs`
# (docs/CMakeLists.txt) from a copy of docs/ with the generated pages beside it.
import os
import sys

project = "nhc"
author = "the nhc authors"
release = os.environ.get("NHC_VERSION", "")
version = release

# The compiled module is imported from the build tree for autodoc (NHC_PYTHON_DIR).
if os.environ.get("NHC_PYTHON_DIR"):
    sys.path.insert(0, os.environ["NHC_PYTHON_DIR"])

extensions = ["myst_parser", "nbsphinx", "sphinx.ext.autodoc", "sphinx.ext.mathjax"]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "**.ipynb_checkpoints", "animate/**", "compare/**/*.md"]
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3
# The pages cite source files by path (examples/…, codegen/…) as text; links between pages resolve.
suppress_warnings = ["myst.header"]

# The notebooks are run by the test python:test_notebooks and here, so the site shows their outputs.
nbsphinx_execute = os.environ.get("NHC_DOCS_EXECUTE", "always")
nbsphinx_timeout = 600
nbsphinx_kernel_name = "python3"

# MathJax from Debian's libjs-mathjax, copied to _static/mathjax by build_docs.cmake (a relative
# mathjax_path is relative to _static): the site works offline.
mathjax_path = "mathjax/MathJax.js?config=TeX-AMS_CHTML"  # CommonHTML output: no font probes
nbsphinx_requirejs_path = ""

html_theme = "furo"
html_title = "nhc — the nonholonomic compiler"
html_static_path = []
autodoc_member_order = "bysource"
autodoc_typehints = "description"


def _bundle_furo_script(app, exception):
    """Debian's furo ships its script as an ES module source (`import Gumshoe from …`) where the
    upstream wheel ships a webpack bundle; loaded as the classic script the theme's page asks for, it
    is a SyntaxError in the browser. Written here as one classic script: gumshoe (a UMD module that
    sets window.Gumshoe) followed by furo.js without its import line."""
    if exception is not None or app.builder.format != "html":
        return
    import furo
    scripts = os.path.join(os.path.dirname(furo.__file__), "theme", "furo", "static", "scripts")
    with open(os.path.join(scripts, "gumshoe-patched.js"), encoding="utf-8") as f:
        gumshoe = f.read()
    with open(os.path.join(scripts, "furo.js"), encoding="utf-8") as f:
        lines = f.read().splitlines(keepends=True)
    if not lines[0].startswith("import Gumshoe"):
        return  # a bundled furo.js (the upstream wheel): nothing to do
    body = "".join(lines[1:])
    with open(os.path.join(app.outdir, "_static", "scripts", "furo.js"), "w", encoding="utf-8") as f:
        f.write(gumshoe + "\n;(function () {\n" + body + "\n})();\n")


NORMALIZE = "/usr/share/javascript/normalize.css/normalize.css"


def _inline_normalize_css(app, exception):
    """Debian's furo.css starts with `@import url(/javascript/normalize.css/normalize.css)`, a path
    on Debian's own web server; a site served from anywhere else gets a 404 there. Inlined from
    Debian's node-normalize.css instead."""
    if exception is not None or app.builder.format != "html":
        return
    css = os.path.join(app.outdir, "_static", "styles", "furo.css")
    with open(css, encoding="utf-8") as f:
        text = f.read()
    line = "@import url(/javascript/normalize.css/normalize.css);"
    if line in text:
        with open(NORMALIZE, encoding="utf-8") as f:
            text = text.replace(line, f.read(), 1)
        with open(css, "w", encoding="utf-8") as f:
            f.write(text)


def setup(app):
    app.connect("build-finished", _bundle_furo_script)
    app.connect("build-finished", _inline_normalize_css)
